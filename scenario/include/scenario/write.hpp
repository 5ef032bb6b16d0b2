#pragma once
// Scenario → scenario YAML (docs/scenarios.md): the inverse of parse_scenario. Tools that build
// scenarios in memory (ocp_campaign's generated and shrunk worlds) write them back as ordinary
// files a user can read, run with `ocp_scenario run` and commit as regression tests.
// parse_scenario(write_scenario_yaml(s)) gives back s (fields the format has; `path`, marks
// and labels are the parser's own).
#include <string>

#include "scenario/model.hpp"

namespace ocp::scenario {

// `header`: comment lines written first (each prefixed with "# "); may be empty.
std::string write_scenario_yaml(const Scenario& scenario, const std::string& header = {});

// "12s", "350ms", "250us": the shortest exact form, as the parser reads it.
std::string duration_text(Micros time);

}  // namespace ocp::scenario
