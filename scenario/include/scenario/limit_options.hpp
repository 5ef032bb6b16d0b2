#pragma once
// --max-events-per-s, the one option of every tool that runs scenario worlds in virtual time
// (ocp_scenario run, ocp_campaign run and check): raises ParseLimits::max_events_per_s.
// Header-only, for the tools' command lines (they link CLI11; the engine does not).
#include <CLI/CLI.hpp>
#include <cstdint>

#include "ocp/cli_checks.hpp"
#include "scenario/parse.hpp"

namespace ocp::scenario {

inline void add_max_events_option(CLI::App& command, std::uint64_t& events_per_s) {
  command.add_option("--max-events-per-s", events_per_s,
                     "raise the ceiling of simulator events per simulated second (default 1000000)")
      ->type_name("N")
      ->check(ocp::cli::whole(1'000, 1'000'000'000'000));
}

// 0: the option was not given, the default stays.
inline void apply_max_events(std::uint64_t events_per_s) {
  if (events_per_s == 0) return;
  ParseLimits limits = parse_limits();
  limits.max_events_per_s = events_per_s;
  set_parse_limits(limits);
}

}  // namespace ocp::scenario
