// Client worlds (client_world.hpp).
#include "campaign/client_world.hpp"

#include <algorithm>
#include <memory>
#include <mutex>
#include <vector>

#include "sim_app/client_process.hpp"
#include "vtime/client_world.hpp"
#include "world/world.hpp"

namespace ocp::campaign {

namespace {

// One client process per vehicle, launched when the world's server for it listens.
using vtime::LaunchedClient;

std::uint16_t port_of(const std::string& address) {
  const auto colon = address.rfind(':');
  return static_cast<std::uint16_t>(std::stoul(address.substr(colon + 1)));
}

// The client processes' end of the world: each must have connected and still be running. One
// that ended before it ever connected could not be started (a harness error, exit 2).
void judge_clients(std::vector<LaunchedClient>& clients, const ClientWatch& watch, SimTime end, WorldOutcome& outcome) {
  for (LaunchedClient& client : clients) {
    const bool running = client.ran_to_the_end();
    if (!running && !watch.ever_connected(client.vehicle)) {
      std::string reason = "the client (" + client.vehicle + ") " +
                           sim_app::describe_exit_status(client.process->exit_status().value_or(-1)) + " before it connected";
      const std::string tail = sim_app::last_lines_of(client.log_path, 5);
      throw scenario::HarnessError(tail.empty() ? reason : reason + "; its last lines:\n" + tail);
    }
    if (!watch.ever_connected(client.vehicle)) {
      ++outcome.violation_count;
      outcome.violations.push_back({Check::client_reconnect, end, client.vehicle, "the client never connected", std::nullopt, false, std::nullopt});
    }
    if (running) continue;
    std::string detail = "the client " + sim_app::describe_exit_status(client.process->exit_status().value_or(-1)) +
                         " during the world";
    const std::string tail = sim_app::last_lines_of(client.log_path, 3);
    if (!tail.empty()) detail += "; its last lines:\n" + tail;
    ++outcome.violation_count;
    outcome.violations.push_back({Check::client_alive, end, client.vehicle, detail, std::nullopt, false, std::nullopt});
  }
}

// The clients stopped, and the CPU they used counted (the campaign's efficiency line).
void stop_and_count(std::vector<LaunchedClient>& clients, WorldOutcome& outcome) {
  for (LaunchedClient& client : clients) {
    client.process->kill();
    outcome.client_cpu_seconds += client.process->cpu_seconds();
  }
}

// A restarted listener refuses connections for a while: the reconnect bound starts after it.
ClientBounds with_listener_restarts(ClientBounds bounds, const scenario::Scenario& world) {
  Micros longest{0};
  for (const scenario::TimelineEvent& event : world.timeline) {
    if (const auto* close = std::get_if<scenario::DisconnectVehicle>(&event.action)) longest = std::max(longest, close->listener_down);
  }
  bounds.reconnect_within += longest;
  return bounds;
}

// A client world's run options: no trace, the Oracle and ClientWatch on its event stream.
scenario::RunOptions judged_by(Oracle& oracle, ClientWatch& watch, const std::function<bool()>& stop) {
  scenario::RunOptions options;
  options.trace = false;
  options.interrupted = stop;
  options.on_built = [&oracle, &watch](World& built) {
    oracle.attach(built);
    watch.attach(built);
  };
  options.on_finished = [&oracle, &watch](World& built) {
    oracle.finish(built);
    watch.finish(built);
  };
  return options;
}

void take_violations(WorldOutcome& outcome, const std::vector<Violation>& violations, std::uint64_t count) {
  outcome.violations.insert(outcome.violations.end(), violations.begin(), violations.end());
  outcome.violation_count += count;
}

}  // namespace

scenario::Scenario for_external_client(scenario::Scenario world, std::uint64_t index, std::optional<Micros> max_world) {
  for (VehicleSpec& vehicle : world.world.vehicles) {
    vehicle.in_process_client = false;
    vehicle.client.misbehave = {};
  }
  // The client under test is the vehicle; the operator side stays as it is without a client.
  world.operator_client.connect = false;
  if (max_world && world.duration > *max_world) world.duration = *max_world;
  std::erase_if(world.timeline, [&](const scenario::TimelineEvent& event) {
    return event.at >= world.duration || std::holds_alternative<scenario::SetMisbehaviour>(event.action) ||
           std::holds_alternative<scenario::SetOperatorMisbehaviour>(event.action);
  });
  add_client_hazards(world, index);
  return world;
}

ClientBounds virtual_time_client_bounds() {
  ClientBounds bounds;
  bounds.echo_current = Micros{20'000};   // two control periods
  bounds.stale_for = Micros{20'000};
  return bounds;
}

namespace {

std::string client_log_path(const ClientRun& run, std::uint64_t index, const std::string& vehicle) {
  return run.log_dir.empty() ? "" : run.log_dir + "/world-" + std::to_string(index) + "-" + vehicle + ".log";
}

// The world in virtual time: the whole oracle, the tight client bounds.
WorldOutcome check_world_with_virtual_client(const scenario::Scenario& world, std::uint64_t index, const ClientRun& run,
                                             const std::function<bool()>& stop, WorldOutcome outcome) {
  Oracle oracle(world, OracleTolerances{});
  ClientWatch watch(with_listener_restarts(run.bounds, world));
  const scenario::RunOptions options = judged_by(oracle, watch, stop);
  vtime::VirtualClientOptions clients;
  clients.command = run.command;
  clients.log_path = [&](const std::string& vehicle) { return client_log_path(run, index, vehicle); };
  clients.controller = run.controller;
  try {
    vtime::VirtualClientRun ran = vtime::run_with_virtual_clients(world, options, clients);
    outcome.cpu_seconds = ran.result.cpu_seconds;
    outcome.events = oracle.events_seen();
    outcome.liveness_checked = oracle.liveness_checked();
    take_violations(outcome, oracle.violations(), oracle.violation_count());
    take_violations(outcome, watch.violations(), watch.violation_count());
    judge_clients(ran.clients, watch, ran.result.ran, outcome);
    stop_and_count(ran.clients, outcome);
  } catch (const scenario::HarnessError& error) {
    outcome.error = error.what();
  } catch (const vtime::VirtualTimeError& error) {
    outcome.error = error.what();
  }
  return outcome;
}

}  // namespace

WorldOutcome check_world_with_client(const scenario::Scenario& world, std::uint64_t index, const ClientRun& run,
                                     const std::function<bool()>& stop) {
  WorldOutcome outcome;
  outcome.index = index;
  outcome.seed = world.seed;
  outcome.duration = world.duration;
  outcome.vehicles = static_cast<int>(world.world.vehicles.size());
  outcome.timeline_events = static_cast<int>(world.timeline.size());
  outcome.hazards = hazards_in(world);
  if (run.time == ClientTime::virtual_time) return check_world_with_virtual_client(world, index, run, stop, std::move(outcome));
  std::vector<LaunchedClient> clients;
  Oracle oracle(world, OracleTolerances{.real_time_slack = real_time_oracle_slack, .judge_timing = false});
  ClientWatch watch(with_listener_restarts(run.bounds, world));
  const scenario::RunOptions options = judged_by(oracle, watch, stop);
  scenario::RealTimeOptions real_time;
  real_time.tcp_port = 0;
  real_time.handle_signals = false;
  real_time.on_listening = [&](const std::string& vehicle, const std::string& address) {
    LaunchedClient client{vehicle, client_log_path(run, index, vehicle), nullptr};
    auto launched = sim_app::ClientProcess::launch({"/bin/sh", "-c", run.command}, port_of(address), client.log_path);
    if (!launched) throw scenario::HarnessError("cannot start the client: " + launched.error().message());
    client.process = std::move(*launched);
    clients.push_back(std::move(client));
  };
  try {
    const scenario::RunResult result = scenario::run_scenario_realtime(world, options, real_time);
    outcome.cpu_seconds = result.cpu_seconds;
    outcome.events = oracle.events_seen();
    outcome.liveness_checked = oracle.liveness_checked();
    take_violations(outcome, oracle.violations(), oracle.violation_count());
    take_violations(outcome, watch.violations(), watch.violation_count());
    judge_clients(clients, watch, result.ran, outcome);
    stop_and_count(clients, outcome);
  } catch (const scenario::HarnessError& error) {
    outcome.error = error.what();
  }
  return outcome;
}

}  // namespace ocp::campaign
