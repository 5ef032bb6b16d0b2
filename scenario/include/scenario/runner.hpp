#pragma once
// Runs one scenario in virtual time: builds the World from the model, installs the gamepad
// script, schedules every timeline action on the executor, attaches the Observer (and the
// TraceRecorder) and runs to the scenario's duration. Same scenario + seed → same trace, byte
// for byte (the World's determinism; the runner draws no randomness of its own).
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "scenario/model.hpp"
#include "scenario/observer.hpp"
#include "world/trace.hpp"

namespace ocp {
class VirtualExecutor;
}

namespace ocp::scenario {

// The world refused to start (a configuration the World rejects): exit code 2, like a bad file.
class HarnessError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct RunOptions {
  std::optional<std::uint64_t> seed;   // overrides the file's seed
  bool trace = true;                   // record the trace (frames without payloads): digest, line count
  bool trace_payloads = false;         // … with every frame's payload bytes
  // Where the trace's lines go: written to this file as the run goes (memory stays flat
  // however long the run: ocp_scenario's trace.jsonl), or, without a file, kept in
  // RunResult::trace_jsonl when trace_in_memory (short runs, tests). Neither: only the digest
  // and line count (ocp_campaign's determinism check).
  std::string trace_file;
  bool trace_in_memory = true;
  // Polled while the run goes (every 100 ms of virtual time, every 50 ms of real time): true
  // stops the run there (Ctrl-C, ocp/interrupt.hpp). Empty: never.
  std::function<bool()> interrupted;
  // For tools that judge a run from its event stream (ocp_campaign's oracle): called with the
  // built World before it starts (subscribe here), and at the end before it stops.
  std::function<void(World&)> on_built;
  std::function<void(World&)> on_finished;
};

struct FiredEvent {
  SimTime at{0};
  std::string name;
  std::string label;
};

struct RunResult {
  std::uint64_t seed = 0;
  SimTime duration{0};
  // Cut short (Ctrl-C) at `ran` < duration: what needs the rest of the timeline is not judged.
  bool interrupted = false;
  SimTime ran{0};
  // The world refused to start, for this reason: only a scenario that expects it
  // (RefusesToStartExpectation) gets a result then; any other is a HarnessError.
  std::optional<std::string> refused_to_start;
  Observations observations;
  std::vector<FiredEvent> fired;
  std::string trace_jsonl;   // empty unless RunOptions::trace and trace_in_memory, without trace_file
  std::uint64_t trace_digest = 0;
  std::uint64_t trace_lines = 0;
  std::uint64_t executor_events = 0;
  double wall_seconds = 0.0;
  double cpu_seconds = 0.0;   // process CPU time of the run (the machine may be shared)
};

RunResult run_scenario(const Scenario& scenario, const RunOptions& options);

// Virtual time with the clock driven from outside (vtime/: external client processes on the
// World's clock): as run_scenario, but `drive` runs the executor to `end` (absolute) and
// returns the time it stopped at.
using VirtualDriver = std::function<SimTime(World& world, VirtualExecutor& executor, SimTime end)>;
RunResult run_scenario_driven(const Scenario& scenario, const RunOptions& options, const VirtualDriver& drive);

// Real time (--realtime): the same World on an AsioExecutor for `duration` of wall time, with
// CSPRNG MAC keys (not reproducible). Every vehicle with `in_process_client: false` gets a TCP
// server for an external vehicle client: the first on `tcp_port`, the next on tcp_port + 1, …
// (0: ephemeral ports). `on_listening(vehicle, address)` tells where.
struct RealTimeOptions {
  std::uint16_t tcp_port = 4000;
  // False: SIGINT/SIGTERM are the caller's (it stops the run through RunOptions::interrupted),
  // as when several worlds run at once on threads (ocp_campaign --client).
  bool handle_signals = true;
  std::function<void(const std::string& vehicle, const std::string& address)> on_listening;
  // Set: the Player's :4001 API gets a TCP server too (an ephemeral port, told here), for one
  // external operator client process (ocp_scenario run --operator-client). The scenario's own
  // operator client must be off (world.operator_client.connect: false).
  std::function<void(const std::string& address)> on_operator_listening;
  // The clock starts when every external client (each external vehicle's, and the operator
  // client's when on_operator_listening is set) has connected (ocp_scenario run -- CMD, or
  // --wait-for-clients), not when the servers start listening: a client's start-up time is no
  // part of the scenario. Waited for at most `connect_timeout`; `client_problem`, polled
  // meanwhile, ends the wait early with its text (a launched client that exited). Either is a
  // HarnessError.
  bool start_at_connection = false;
  std::chrono::milliseconds connect_timeout{10'000};
  std::function<std::optional<std::string>()> client_problem;
};
RunResult run_scenario_realtime(const Scenario& scenario, const RunOptions& options,
                                const RealTimeOptions& real_time);

// Whether any expectation of the scenario needs control payloads decoded.
bool needs_controller_check(const Scenario& scenario);
// Whether the scenario expects its world to refuse to start.
bool expects_refusal(const Scenario& scenario);
// Whether any expectation needs link events (feedback_gap_ms, lost_*).
bool needs_link_events(const Scenario& scenario);

}  // namespace ocp::scenario
