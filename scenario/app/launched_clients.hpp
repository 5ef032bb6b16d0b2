#pragma once
// `ocp_scenario run FILE -- CMD ARGS…`: the tool launches the external clients itself, one
// process of CMD per vehicle with `in_process_client: false` ({port} and $OCP_PORT: that
// vehicle's Streamer port), and with --operator-client one operator client process on the
// Player's :4001 API, in both times.
//   * virtual time (the default): every process lives on the World's clock through the shim
//     (vtime/, docs/virtual-time.md); the run is exact and reproducible from its seed. A client
//     that cannot (a static binary, Go) is exit 2 with the reason; a busy loop or a hang ends at
//     the wall-clock watchdog (--world-timeout).
//   * real time: the clock starts when every launched client, the operator client's included,
//     has connected (at most --connect-timeout-s after the launch; then exit 2).
// Each launched process must connect and still run when the world ends: a verdict of its own
// (kind "client"). One that exits before it ever connected is a harness error (exit 2) with the
// last lines it wrote.
#include <string>
#include <vector>

#include "scenario/runner.hpp"
#include "scenario/verdicts.hpp"

namespace ocp::scenario {

struct LaunchOptions {
  std::vector<std::string> command;     // -- CMD ARGS…; empty: no vehicle client is launched
  std::string operator_command;         // --operator-client, a shell line with {port}; "" → none
  bool virtual_time = true;
  double connect_timeout_s = 10.0;      // real time: every launched client connected by then
  double world_timeout_s = 120.0;       // virtual time: wall seconds the run may take
  std::string log_dir;                  // the clients' output, <log_dir>/client-<name>.log
};

struct LaunchedRun {
  RunResult result;
  std::vector<Verdict> client_verdicts;   // one per launched process
};

// The scenario's problem with launching (no vehicle to launch for, an operator client twice),
// or "" when it can be run so.
std::string launch_problem(const Scenario& scenario, const LaunchOptions& launch);

// Throws HarnessError: a client that cannot be started, cannot run in virtual time, exited
// before it connected, or (real time) did not connect in time.
LaunchedRun run_with_launched_clients(const Scenario& scenario, const RunOptions& options, const LaunchOptions& launch);

}  // namespace ocp::scenario
