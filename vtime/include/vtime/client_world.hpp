#pragma once
// A scenario's World with external client processes in virtual time (docs/virtual-time.md):
// one process of `command` per vehicle without an in-process client, each on its own
// Streamer port, all on the World's VirtualExecutor through one Controller.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "scenario/runner.hpp"
#include "sim_app/client_process.hpp"
#include "vtime/controller.hpp"

namespace ocp::vtime {

struct VirtualClientOptions {
  // A shell command line (/bin/sh -c) with "{port}" replaced by its Streamer's port (also in
  // env OCP_PORT), or an argv when `argv` is set.
  std::string command;
  std::vector<std::string> argv;
  // Each client's output file ("" → /dev/null), by vehicle.
  std::function<std::string(const std::string& vehicle)> log_path;
  ControllerOptions controller;
};

struct LaunchedClient {
  std::string vehicle;
  std::string log_path;
  std::unique_ptr<sim_app::ClientProcess> process;
};

struct VirtualClientRun {
  scenario::RunResult result;
  // Still running (if they did) when the run ended; killed when this goes.
  std::vector<LaunchedClient> clients;
  ControllerStats stats;
};

// Throws VirtualTimeError (a client that cannot live in virtual time, a busy loop, the
// watchdog) and scenario::HarnessError (a client that cannot be started).
VirtualClientRun run_with_virtual_clients(const scenario::Scenario& scenario, const scenario::RunOptions& options,
                                          const VirtualClientOptions& clients);

}  // namespace ocp::vtime
