// A scenario in real time (runner.hpp, --realtime): the World on sim_app's RealTimeRunner,
// TCP servers for external vehicle clients (and, when asked, an operator client on the
// Player's :4001 API). Timeline and verdicts are the virtual run's; only the clock and the MAC
// keys differ, so verdict windows must allow for real scheduling jitter. The servers listen
// before the World is built, so that with start_at_connection the clients can connect first:
// their connections are held and handed to the World when its clock starts.
#include <fmt/format.h>

#include <map>
#include <memory>
#include <set>
#include <utility>
#include <vector>

#include "ocp/asio/tcp_server.hpp"
#include "run_world.hpp"
#include "scenario/runner.hpp"
#include "sim_app/real_time_runner.hpp"

namespace ocp::scenario {

namespace {

// One external client's listening socket: a vehicle's Streamer port, or (vehicle "") the
// Player's :4001 API. Connections before the World exists are held.
struct ClientServer {
  std::string vehicle;
  std::unique_ptr<TcpServer> server;
  bool for_operator() const { return vehicle.empty(); }
};

struct Servers {
  World* world = nullptr;
  std::vector<ClientServer> list;
  std::vector<std::pair<std::string, std::shared_ptr<ByteStream>>> held;
  std::set<std::string> connected;

  void accept(const std::string& vehicle, std::shared_ptr<ByteStream> stream) {
    connected.insert(vehicle);
    if (world == nullptr) {
      held.emplace_back(vehicle, std::move(stream));
    } else if (vehicle.empty()) {
      world->player().accept_client_connection(std::move(stream));
    } else {
      world->accept_vehicle_connection(vehicle, std::move(stream));
    }
  }
  // The World is built: the connections held until now go to it, in the order they came.
  void hand_over(World& built) {
    world = &built;
    for (auto& [vehicle, stream] : held) accept(vehicle, std::move(stream));
    held.clear();
  }
};

std::unique_ptr<TcpServer> listen_for(sim_app::RealTimeRunner& runner, Servers& servers, const std::string& vehicle,
                                      std::uint16_t port) {
  auto server = std::make_unique<TcpServer>(runner.io(), [&servers, vehicle](std::shared_ptr<ByteStream> stream) {
    servers.accept(vehicle, std::move(stream));
  });
  if (auto status = server->listen(TcpServerOptions{port, false}); !status) {
    throw HarnessError((vehicle.empty() ? std::string("the operator API") : "vehicle " + vehicle) + ": " +
                       status.error().message());
  }
  return server;
}

void listen_for_clients(const Scenario& scenario, const RealTimeOptions& real_time, sim_app::RealTimeRunner& runner,
                        Servers& servers) {
  std::uint16_t port = real_time.tcp_port;
  for (const VehicleSpec& spec : scenario.world.vehicles) {
    if (spec.in_process_client) continue;
    auto server = listen_for(runner, servers, spec.name, port);
    if (real_time.on_listening) real_time.on_listening(spec.name, server->local_address());
    servers.list.push_back({spec.name, std::move(server)});
    if (port != 0) ++port;
  }
  if (real_time.on_operator_listening) {
    auto server = listen_for(runner, servers, "", 0);
    real_time.on_operator_listening(server->local_address());
    servers.list.push_back({"", std::move(server)});
  }
}

// "truck-1, truck-2 and the Player's :4001 API": where no client has connected yet.
std::string not_connected(const Servers& servers) {
  std::string vehicles;
  bool operator_missing = false;
  for (const ClientServer& server : servers.list) {
    if (servers.connected.contains(server.vehicle)) continue;
    if (server.for_operator()) operator_missing = true;
    else vehicles += (vehicles.empty() ? "" : ", ") + server.vehicle;
  }
  if (!operator_missing) return vehicles;
  return vehicles.empty() ? "the Player's :4001 API" : vehicles + " and the Player's :4001 API";
}

// Runs the event loop until every external client has a connection (start_at_connection).
void wait_for_connections(const RealTimeOptions& real_time, sim_app::RealTimeRunner& runner, const Servers& servers,
                          const std::function<bool()>& interrupted) {
  const auto give_up = std::chrono::steady_clock::now() + real_time.connect_timeout;
  while (servers.connected.size() < servers.list.size()) {
    if (interrupted && interrupted()) return;
    if (real_time.client_problem) {
      if (auto problem = real_time.client_problem()) throw HarnessError(*problem);
    }
    if (std::chrono::steady_clock::now() >= give_up) {
      throw HarnessError(fmt::format("no client connected for {} within {:g} s", not_connected(servers),
                                     static_cast<double>(real_time.connect_timeout.count()) / 1000.0));
    }
    if (runner.io().stopped()) runner.io().restart();
    (void)runner.io().run_one_for(std::chrono::milliseconds(10));
  }
}

}  // namespace

RunResult run_scenario_realtime(const Scenario& scenario, const RunOptions& options,
                                const RealTimeOptions& real_time) {
  sim_app::RealTimeRunner runner(real_time.handle_signals ? sim_app::RealTimeRunner::Signals::handle
                                                         : sim_app::RealTimeRunner::Signals::leave_to_caller);   // first: destroyed last
  Servers servers;
  listen_for_clients(scenario, real_time, runner, servers);
  if (real_time.start_at_connection) wait_for_connections(real_time, runner, servers, options.interrupted);
  std::string relisten_error;   // a restarted listener that could not have its port back
  RunResult result = run_world(runner.executor(), scenario, options, false, [&](World& world, SimTime end) {
    servers.hand_over(world);
    for (ClientServer& entry : servers.list) {
      if (entry.for_operator()) continue;
      // A restart of the Streamer's listener (disconnect with listener_down): the same port
      // refuses connections that long, then listens again.
      world.set_vehicle_listener(entry.vehicle, [&, raw = entry.server.get(), bound = entry.server->port(), name = entry.vehicle](Micros down) {
        raw->stop();
        runner.executor().call_after(down, [&, raw, bound, name] {
          if (auto status = raw->listen(TcpServerOptions{bound, false}); !status && relisten_error.empty()) {
            relisten_error = "vehicle " + name + ": the restarted listener could not listen again: " + status.error().message();
            runner.request_stop("listener lost");
          }
        });
      });
    }
    // The runner catches SIGINT / SIGTERM itself while it runs; a stop before `end` is one.
    SimTime stopped = end;
    runner.set_on_shutdown([&](const std::string&) {
      stopped = runner.executor().now();
      for (auto& entry : servers.list) entry.server->stop();   // no new vehicle once the run is over
    });
    PeriodicTimer interrupt_poll(runner.executor(), Micros{50'000}, [&](SimTime) {
      if (options.interrupted && options.interrupted()) runner.request_stop("interrupted");
    });
    interrupt_poll.start(runner.executor().now());
    (void)runner.run(end - runner.executor().now());
    servers.world = nullptr;
    return stopped;
  });
  if (!relisten_error.empty()) throw HarnessError(relisten_error);
  return result;
}

}  // namespace ocp::scenario
