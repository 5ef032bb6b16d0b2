#pragma once
// Runs the selected cases: one StreamerHost per worker (its own io_context, thread and port),
// the client under test either external (waits on --port) or launched per worker, or per case
// with --restart-per-case. Independent cases run concurrently with jobs > 1 (launched clients
// only: each worker has its own client and port).
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "conformance/control_frames.hpp"
#include "conformance/case.hpp"
#include "conformance/vehicle_cases.hpp"
#include "vtime/controller.hpp"

namespace ocp::conformance {

struct RunOptions {
  std::vector<std::string> command;  // empty: wait for an external client on `port`
  std::uint16_t port = 4000;         // with a command: 0 = ephemeral (one per worker)
  bool restart_per_case = false;
  unsigned jobs = 1;
  double timeout_scale = 1.0;
  // A launched client that has not connected this long after its launch (or exited before it
  // did) cannot be graded: the run stops with a harness error (exit 2). Scaled by timeout_scale.
  std::chrono::milliseconds connect_timeout{3'000};
  std::string client_log_dir;    // launched clients' output (one file each); "" → /dev/null
  bool client_logs_kept = true;  // false: a temporary folder, quoted from but never named
  InterlockButtons interlock;    // how the §10 cases enable and stop the client's drive
  // Virtual time (--time virtual, launched clients only): each worker's World and its client on
  // one virtual clock (StreamerHost, vtime::Controller); case timeouts and every wait are virtual.
  bool virtual_time = false;
  vtime::ControllerOptions controller;   // the shim, the wall-clock watchdog of each wait
  // Progress: each result in case order (with jobs > 1 a result waits for the cases before it).
  std::function<void(const CaseResult&)> on_result;
  // Ctrl-C: polled while cases wait; true stops the run. The case in progress gets no verdict.
  std::function<bool()> stop_requested;
};

struct RunSummary {
  std::vector<CaseResult> results;  // in case order
  double duration_ms = 0.0;
  std::string harness_error;  // non-empty: the run could not be done (exit 2)
  bool interrupted = false;   // stopped by Ctrl-C: `results` holds the cases finished before
  std::size_t cases_selected = 0;
};

RunSummary run_cases(const std::vector<VehicleCase>& cases, const RunOptions& options);

// Case selection: comma-separated glob patterns ('*' and '?') over ids; empty = all.
bool matches_any(const std::string& id, const std::string& patterns);
std::vector<VehicleCase> select_cases(std::vector<VehicleCase> cases, const std::string& include,
                                      const std::string& exclude);

}  // namespace ocp::conformance
