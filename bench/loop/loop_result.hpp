#pragma once
// What one `ocp_bench loop` run measured, ready for the three outputs (loop_report.hpp).
#include <optional>
#include <string>
#include <vector>

#include "loop_recorder.hpp"
#include "stats.hpp"

namespace ocp::bench {

// One Streamer and the client that answered it.
struct ClientFigures {
  std::string name;                  // "client", "bare_client", "timer_client"
  Summary echo_us;                   // control frame out → first response with its pair
  std::uint64_t control_frames = 0;
  std::uint64_t responses = 0;
  double responses_per_s = 0;
  double max_response_gap_ms = 0;    // largest gap between consecutive responses
  Summary latency_ms;                // LatencySample::latency_ms (SPEC §5.7)
  Summary tick_lateness_us;          // LatencySample::tick_lateness
  std::uint64_t connections = 0;
  std::vector<FaultRecord> faults;
  std::vector<double> echo_delays_us;        // for the histogram
  std::vector<TimePoint> echo_series_us;     // for the time series
  std::vector<TimePoint> latency_series_ms;
  std::vector<double> response_times_s;
};

// One pass/fail gate of the run (loop_gates.hpp).
struct GateResult {
  std::string name;       // "client echo delay p50"
  std::string expected;   // "≤ 200 µs"
  std::string actual;     // "103 µs"
  bool passed = false;
};

struct LoopResult {
  std::string command;               // what was launched after `--`, or "" when waiting
  std::uint16_t port = 0;
  double duration_s = 0;
  std::optional<int> child_exit;     // the child's exit status when it ended before the bench
  bool interrupted = false;          // Ctrl-C cut the measurement short
  ClientFigures client;
  std::optional<Summary> floor_echo_us;        // --compare: bare blocking-socket echo
  std::vector<double> floor_echo_delays_us;
  std::optional<ClientFigures> bare_client;    // --compare: blocking read, answers at once
  std::optional<ClientFigures> timer_client;   // --compare: answers on its own 10 ms timer
  std::vector<GateResult> gates;               // the --max-* / --fail-on-fault the run was held to
  // Faults raised once the client was connected (clears, and what the Streamer raised while
  // alone, do not count).
  std::size_t faults_after_connect() const;
};

ClientFigures figures_from(const std::string& name, const LoopRecorder& recorder, double duration_s);

}  // namespace ocp::bench
