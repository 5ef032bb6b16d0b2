#include "loop_gates.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace ocp::bench {

std::vector<GateResult> evaluate_gates(const LoopOptions& options, const LoopResult& result) {
  std::vector<GateResult> gates;
  const Summary& echo = result.client.echo_us;
  // No echo at all fails every echo gate: a budget is not met by a client that never answered.
  auto at_most = [&](const char* name, double actual, double limit, const char* unit) {
    const bool measured = echo.count > 0;
    gates.push_back({name, fmt::format("≤ {:g} {}", limit, unit),
                     measured ? fmt::format("{:.3g} {}", actual, unit) : "no echo measured",
                     measured && actual <= limit});
  };
  if (options.max_echo_p50_us) at_most("client echo delay p50", echo.p50, *options.max_echo_p50_us, "µs");
  if (options.max_echo_p99_us) at_most("client echo delay p99", echo.p99, *options.max_echo_p99_us, "µs");
  if (options.max_floor_ratio) {
    const bool measured = echo.count > 0 && result.floor_echo_us && result.floor_echo_us->p50 > 0;
    const double ratio = measured ? echo.p50 / result.floor_echo_us->p50 : 0.0;
    gates.push_back({"client echo p50 ÷ machine floor p50", fmt::format("≤ {:g}×", *options.max_floor_ratio),
                     measured ? fmt::format("{:.2f}×", ratio) : "not measured", measured && ratio <= *options.max_floor_ratio});
  }
  const ClientFigures& client = result.client;
  if (options.min_response_rate) {
    gates.push_back({"client responses per second", fmt::format("≥ {:g} /s", *options.min_response_rate),
                     fmt::format("{:.1f} /s", client.responses_per_s), client.responses_per_s >= *options.min_response_rate});
  }
  if (options.max_response_gap_ms) {
    const bool measured = client.responses >= 2;
    gates.push_back({"longest gap between client responses", fmt::format("≤ {:g} ms", *options.max_response_gap_ms),
                     measured ? fmt::format("{:.1f} ms", client.max_response_gap_ms) : "fewer than 2 responses",
                     measured && client.max_response_gap_ms <= *options.max_response_gap_ms});
  }
  if (options.max_latency_p99_ms) {
    const bool measured = client.latency_ms.count > 0;
    gates.push_back({"loop latency p99 (Streamer)", fmt::format("≤ {:g} ms", *options.max_latency_p99_ms),
                     measured ? fmt::format("{:.3g} ms", client.latency_ms.p99) : "no latency measured",
                     measured && client.latency_ms.p99 <= *options.max_latency_p99_ms});
  }
  if (options.fail_on_fault) {
    const std::size_t faults = result.faults_after_connect();
    gates.push_back({"faults raised after the client connected", "none", faults == 0 ? "none" : fmt::format("{}", faults),
                     faults == 0});
  }
  return gates;
}

bool all_passed(const std::vector<GateResult>& gates) {
  return std::all_of(gates.begin(), gates.end(), [](const GateResult& gate) { return gate.passed; });
}

}  // namespace ocp::bench
