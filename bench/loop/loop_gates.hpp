#pragma once
// The gates of `ocp_bench loop` (--max-echo-p50-us, --max-echo-p99-us, --max-floor-ratio,
// --min-response-rate, --max-response-gap-ms, --max-latency-p99-ms, --fail-on-fault): the run's figures against the budget a team holds its client to. Each
// gives ✓/✗ with expected against actual; any ✗ makes the exit code 1.
#include <vector>

#include "loop_command.hpp"
#include "loop_result.hpp"

namespace ocp::bench {

// Only the gates that were asked for, in a fixed order.
std::vector<GateResult> evaluate_gates(const LoopOptions& options, const LoopResult& result);
bool all_passed(const std::vector<GateResult>& gates);

}  // namespace ocp::bench
