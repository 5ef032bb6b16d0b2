// A scenario in real time (runner.hpp, --realtime): the World on sim_app's RealTimeRunner,
// TCP servers for external vehicle clients. Timeline and verdicts are the virtual run's; only
// the clock and the MAC keys differ, so verdict windows must allow for real scheduling jitter.
#include <memory>
#include <vector>

#include "ocp/asio/tcp_server.hpp"
#include "run_world.hpp"
#include "scenario/runner.hpp"
#include "sim_app/real_time_runner.hpp"

namespace ocp::scenario {

RunResult run_scenario_realtime(const Scenario& scenario, const RunOptions& options,
                                const RealTimeOptions& real_time) {
  sim_app::RealTimeRunner runner(real_time.handle_signals ? sim_app::RealTimeRunner::Signals::handle
                                                         : sim_app::RealTimeRunner::Signals::leave_to_caller);   // first: destroyed last
  std::vector<std::unique_ptr<TcpServer>> servers;
  std::string relisten_error;   // a restarted listener that could not have its port back
  RunResult result = run_world(runner.executor(), scenario, options, false, [&](World& world, SimTime end) {
    std::uint16_t port = real_time.tcp_port;
    for (const VehicleSpec& spec : scenario.world.vehicles) {
      if (spec.in_process_client) continue;
      auto server = std::make_unique<TcpServer>(runner.io(), [&world, name = spec.name](std::shared_ptr<ByteStream> stream) {
        world.accept_vehicle_connection(name, std::move(stream));
      });
      if (auto status = server->listen(TcpServerOptions{port, false}); !status) {
        throw HarnessError("vehicle " + spec.name + ": " + status.error().message());
      }
      if (real_time.on_listening) real_time.on_listening(spec.name, server->local_address());
      // A restart of the Streamer's listener (disconnect with listener_down): the same port
      // refuses connections that long, then listens again.
      world.set_vehicle_listener(spec.name, [&, raw = server.get(), bound = server->port(), name = spec.name](Micros down) {
        raw->stop();
        runner.executor().call_after(down, [&, raw, bound, name] {
          if (auto status = raw->listen(TcpServerOptions{bound, false}); !status && relisten_error.empty()) {
            relisten_error = "vehicle " + name + ": the restarted listener could not listen again: " + status.error().message();
            runner.request_stop("listener lost");
          }
        });
      });
      servers.push_back(std::move(server));
      if (port != 0) ++port;
    }
    // The runner catches SIGINT / SIGTERM itself while it runs; a stop before `end` is one.
    SimTime stopped = end;
    runner.set_on_shutdown([&](const std::string&) {
      stopped = runner.executor().now();
      for (auto& server : servers) server->stop();   // no new vehicle once the run is over
    });
    PeriodicTimer interrupt_poll(runner.executor(), Micros{50'000}, [&](SimTime) {
      if (options.interrupted && options.interrupted()) runner.request_stop("interrupted");
    });
    interrupt_poll.start(runner.executor().now());
    (void)runner.run(end - runner.executor().now());
    return stopped;
  });
  if (!relisten_error.empty()) throw HarnessError(relisten_error);
  return result;
}

}  // namespace ocp::scenario
