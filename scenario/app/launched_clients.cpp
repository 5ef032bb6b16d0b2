// `ocp_scenario run FILE -- CMD` (launched_clients.hpp).
#include "launched_clients.hpp"

#include <fmt/format.h>

#include <chrono>
#include <map>

#include "sim_app/client_process.hpp"
#include "vtime/client_world.hpp"
#include "world/world.hpp"

namespace ocp::scenario {

namespace {

using vtime::LaunchedClient;

std::vector<std::string> external_vehicles(const Scenario& scenario) {
  std::vector<std::string> names;
  for (const VehicleSpec& spec : scenario.world.vehicles) {
    if (!spec.in_process_client) names.push_back(spec.name);
  }
  return names;
}

std::string log_path(const LaunchOptions& launch, const std::string& name) {
  return launch.log_dir.empty() ? "" : launch.log_dir + "/client-" + name + ".log";
}

std::string who(const std::string& name) {
  return name == vtime::operator_name ? "the operator client" : "the client (" + name + ")";
}

// How many connections each launched client made, read off the World when the run ends.
using Connections = std::map<std::string, std::uint64_t>;
RunOptions counting_connections(RunOptions options, const Scenario& scenario, Connections& connections) {
  options.on_finished = [&connections, names = external_vehicles(scenario), chained = options.on_finished](World& world) {
    for (const std::string& name : names) connections[name] = world.streamer(name).stats().connections_accepted;
    connections[vtime::operator_name] = world.player().stats().client_connections_accepted;
    if (chained) chained(world);
  };
  return options;
}

// A launched process's verdict: it connected, and still runs when the world ends. One that
// exited before it ever connected could not be tested at all: a harness error.
Verdict judge(LaunchedClient& client, std::uint64_t connections) {
  Verdict verdict;
  verdict.kind = "client";
  verdict.title = who(client.vehicle) + " connects and runs to the end of the world";
  verdict.expected = "connected, still running when the world ends";
  const bool running = client.ran_to_the_end();
  const std::string status = running ? "" : sim_app::describe_exit_status(client.process->exit_status().value_or(-1));
  const std::string tail = sim_app::last_lines_of(client.log_path, 5);
  const std::string lines = tail.empty() ? "" : "; its last lines:" + tail;
  if (!running && connections == 0) throw HarnessError(who(client.vehicle) + " " + status + " before it connected" + lines);
  if (connections == 0) {
    verdict.actual = "never connected";
  } else if (!running) {
    verdict.actual = fmt::format("connected {} time(s), then {} during the world{}", connections, status, lines);
  } else {
    verdict.passed = true;
    verdict.actual = fmt::format("connected {} time(s), running at the end", connections);
  }
  return verdict;
}

LaunchedRun run_virtual(const Scenario& scenario, const RunOptions& options, const LaunchOptions& launch) {
  vtime::VirtualClientOptions clients;
  clients.argv = launch.command;
  clients.operator_command = launch.operator_command;
  clients.log_path = [&launch](const std::string& name) { return log_path(launch, name); };
  clients.controller.shim_path = vtime::find_shim();
  clients.controller.watchdog = std::chrono::milliseconds(static_cast<std::int64_t>(launch.world_timeout_s * 1000));
  if (clients.controller.shim_path.empty()) {
    throw HarnessError("--time virtual needs the shim libocp_vtime_shim.so (beside the program in ../lib, or in "
                       "$OCP_VTIME_SHIM); use --time real");
  }
  Connections connections;
  vtime::VirtualClientRun ran;
  try {
    ran = vtime::run_with_virtual_clients(scenario, counting_connections(options, scenario, connections), clients);
  } catch (const vtime::VirtualTimeError& error) {
    throw HarnessError(error.what());
  }
  LaunchedRun out{std::move(ran.result), {}};
  for (LaunchedClient& client : ran.clients) out.client_verdicts.push_back(judge(client, connections[client.vehicle]));
  if (ran.operator_client) out.client_verdicts.push_back(judge(*ran.operator_client, connections[vtime::operator_name]));
  return out;
}

// A launched client that exited while the run waits for the connections, in words.
std::optional<std::string> exited_before_connecting(std::vector<LaunchedClient>& clients) {
  for (LaunchedClient& client : clients) {
    if (client.process->running()) continue;
    const std::string tail = sim_app::last_lines_of(client.log_path, 5);
    return who(client.vehicle) + " " + sim_app::describe_exit_status(client.process->exit_status().value_or(-1)) +
           " before it connected" + (tail.empty() ? "" : "; its last lines:" + tail);
  }
  return std::nullopt;
}

// The operator client's command line: a shell line, as in virtual time (vtime/client_world.hpp).
std::vector<std::string> shell_line(const std::string& line) { return {"/bin/sh", "-c", line}; }

// Starts one client process on `address`'s port (real time: no shim), kept in `clients`.
void launch_real(std::vector<LaunchedClient>& clients, const std::string& name, const std::vector<std::string>& command,
                 const std::string& address, const LaunchOptions& launch) {
  LaunchedClient client{name, log_path(launch, name), nullptr};
  const auto port = static_cast<std::uint16_t>(std::stoul(address.substr(address.rfind(':') + 1)));
  auto launched = sim_app::ClientProcess::launch(command, port, client.log_path);
  if (!launched) throw HarnessError("cannot start " + who(name) + ": " + launched.error().message());
  client.process = std::move(*launched);
  clients.push_back(std::move(client));
}

LaunchedRun run_real(const Scenario& scenario, const RunOptions& options, const LaunchOptions& launch) {
  std::vector<LaunchedClient> clients;   // the vehicles' and the operator client (vtime::operator_name)
  RealTimeOptions real_time;
  real_time.tcp_port = 0;
  real_time.start_at_connection = true;
  real_time.connect_timeout = std::chrono::milliseconds(static_cast<std::int64_t>(launch.connect_timeout_s * 1000));
  real_time.on_listening = [&](const std::string& vehicle, const std::string& address) {
    launch_real(clients, vehicle, launch.command, address, launch);
  };
  if (!launch.operator_command.empty()) {
    real_time.on_operator_listening = [&](const std::string& address) {
      launch_real(clients, vtime::operator_name, shell_line(launch.operator_command), address, launch);
    };
  }
  real_time.client_problem = [&clients] { return exited_before_connecting(clients); };
  Connections connections;
  LaunchedRun out{run_scenario_realtime(scenario, counting_connections(options, scenario, connections), real_time), {}};
  for (LaunchedClient& client : clients) out.client_verdicts.push_back(judge(client, connections[client.vehicle]));
  return out;
}

}  // namespace

std::string launch_problem(const Scenario& scenario, const LaunchOptions& launch) {
  const std::vector<std::string> external = external_vehicles(scenario);
  if (!launch.command.empty() && external.empty()) {
    return "-- CMD launches a client for each vehicle with in_process_client: false, and this scenario has none";
  }
  if (launch.command.empty() && !external.empty()) {
    return "vehicle " + external.front() + " has in_process_client: false: give its client as -- CMD ARGS…";
  }
  if (!launch.operator_command.empty() && scenario.operator_client.connect) {
    return "--operator-client takes the Player's :4001 API, and this scenario has its own operator client "
           "(world.operator_client.connect: true)";
  }
  return "";
}

LaunchedRun run_with_launched_clients(const Scenario& scenario, const RunOptions& options, const LaunchOptions& launch) {
  return launch.virtual_time ? run_virtual(scenario, options, launch) : run_real(scenario, options, launch);
}

}  // namespace ocp::scenario
