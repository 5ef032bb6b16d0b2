#pragma once
// The three outputs of `ocp_bench loop`: a terminal table, a JSON document (--json) and a
// self-contained HTML page with inline SVG (--html: echo-delay histogram and time series; no
// scripts, no network).
#include <ostream>
#include <string>

#include "loop_result.hpp"

namespace ocp::bench {

void print_table(std::ostream& out, const LoopResult& result);
std::string to_json(const LoopResult& result);
std::string to_html(const LoopResult& result);

}  // namespace ocp::bench
