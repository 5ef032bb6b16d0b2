#pragma once
// A scenario's World with external client processes in virtual time (docs/virtual-time.md):
// one process of `command` per vehicle without an in-process client, each on its own
// Streamer port, and (when given) one operator client process on the Player's :4001 API, all
// on the World's VirtualExecutor through one Controller.
#include <functional>
#include <memory>
#include <optional>
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
  // Each client's output file ("" → /dev/null), by vehicle (operator_name for the operator client).
  std::function<std::string(const std::string& vehicle)> log_path;
  // The operator client (SPEC §4.2), as `command`/`argv`, with "{port}" the Player's :4001 port
  // (a free one). Both empty: none. The scenario's in-process operator client must be off
  // (operator_client.connect: false), or the Player refuses one of the two.
  std::string operator_command;
  std::vector<std::string> operator_argv;
  ControllerOptions controller;
};

// LaunchedClient::vehicle of the operator client.
inline constexpr const char* operator_name = "operator";

struct LaunchedClient {
  std::string vehicle;
  std::string log_path;
  std::unique_ptr<sim_app::ClientProcess> process;
  // Whether it still ran when the world ended. Asked afterwards, a process may have ended
  // already: a wait it was in returns once the Controller is gone (a `sleep 600` exits).
  bool running_at_end = false;
  // What a judge asks: it ran to the end of the world (a real-time run, which sets no
  // running_at_end, asks the process now).
  bool ran_to_the_end() const { return running_at_end || process->running(); }
};

struct VirtualClientRun {
  scenario::RunResult result;
  // Still running (if they did) when the run ended; killed when this goes.
  std::vector<LaunchedClient> clients;
  std::optional<LaunchedClient> operator_client;   // when VirtualClientOptions asked for one
  ControllerStats stats;
};

// Throws VirtualTimeError (a client that cannot live in virtual time, a busy loop, the
// watchdog) and scenario::HarnessError (a client that cannot be started).
VirtualClientRun run_with_virtual_clients(const scenario::Scenario& scenario, const scenario::RunOptions& options,
                                          const VirtualClientOptions& clients);

}  // namespace ocp::vtime
