#pragma once
// `ocp_bench loop`: a Streamer with a simulated operator on 127.0.0.1, the client under test
// connected to it (launched after `--`, or whoever connects to --port), measured for
// --duration-s from the Streamer's event stream. See docs/benchmarks.md ("Loop").
#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

namespace ocp::bench {

struct LoopOptions {
  std::optional<std::uint16_t> port;   // unset: 4000 when waiting, ephemeral with a command
  double duration_s = 10.0;
  double connect_timeout_s = 10.0;
  std::string json_path, html_path;
  bool compare = false;
  bool quiet = false;                  // no progress line
  // Gates (loop_gates.hpp): each is printed ✓/✗ with expected against actual; one that fails
  // makes the exit code 1, so a team's CI can hold its client to a budget.
  std::optional<double> max_echo_p50_us, max_echo_p99_us;
  std::optional<double> max_floor_ratio;   // client echo p50 ÷ machine floor p50; needs --compare
  bool fail_on_fault = false;              // any fault the Streamer raised once the client was there
  // What matters to a loop besides the echo delay: a client answering 19.8 times a second can
  // echo fast and still starve the loop.
  std::optional<double> min_response_rate;      // responses per second
  std::optional<double> max_response_gap_ms;    // longest silence between two responses
  std::optional<double> max_latency_p99_ms;     // the Streamer's measured loop latency
  std::vector<std::string> command;    // after `--`
};

CLI::App* add_loop_command(CLI::App& app, LoopOptions& options);
// Exit code: 0 measured and every gate passed, 1 a gate failed or the client exited once
// measured, 2 the run could not be done (port busy, no client, client exited before it
// connected, a report not written), 130 Ctrl-C (the figures so far, marked interrupted).
int run_loop(const LoopOptions& options);

}  // namespace ocp::bench
