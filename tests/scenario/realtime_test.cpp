// --realtime: the same engine on a real clock, with an external vehicle client over TCP (the
// reference client's TCP runner, on its own thread and io_context as a separate process would be).
#include <boost/asio/io_context.hpp>

#include <future>
#include <thread>

#include "ocp/asio/executor.hpp"
#include "scenario_test_support.hpp"
#include "vehicle_app/tcp_runner.hpp"

namespace ocp::scenario {
namespace {

TEST(ScenarioRealTime, ExternalVehicleClientOverTcp) {
  const Scenario scenario = parse_scenario(R"(seed: 1
duration: 2s
world:
  gamepad: drive
  vehicles:
    - name: truck-1
      in_process_client: false
      link: {delay: 10ms}
expect:
  faults:
    - {fault: VehicleNoResponse, cleared: {after: 0s, within: 1s}}
    - {fault: InvalidMac, never: true, from: 1.5s}
  thresholds:
    latency_ms: ["count > 50", "p(50) < 200"]
)", "realtime.yaml");
  std::promise<std::uint16_t> port_promise;
  auto port_future = port_promise.get_future();
  RealTimeOptions real_time;
  real_time.tcp_port = 0;   // ephemeral: tests never fight over :4000
  real_time.on_listening = [&](const std::string& vehicle, const std::string& address) {
    EXPECT_EQ(vehicle, "truck-1");
    port_promise.set_value(static_cast<std::uint16_t>(std::stoi(address.substr(address.rfind(':') + 1))));
  };
  std::thread vehicle([&] {
    const std::uint16_t port = port_future.get();
    boost::asio::io_context io;
    AsioExecutor executor(io);
    VehicleClient client(executor, VehicleClientConfig{}, Logger(executor, "vehicle", make_null_sink()));
    TcpRunnerConfig config;
    config.server.port = port;
    TcpRunner runner(executor, client, config, Logger(executor, "runner", make_null_sink()));
    runner.start();
    io.run_for(std::chrono::milliseconds(2300));
    runner.stop();
  });
  RunOptions options;
  options.trace = false;
  const RunResult run = run_scenario_realtime(scenario, options, real_time);
  vehicle.join();
  const std::vector<Verdict> verdicts = evaluate(scenario, run);
  EXPECT_GT(verdicts.size(), 0u) << "no verdict: the expectations proved nothing";
  for (const Verdict& verdict : verdicts) {
    EXPECT_TRUE(verdict.passed) << verdict.title << "\n  expected " << verdict.expected << "\n  actual   " << verdict.actual;
  }
  EXPECT_GE(run.wall_seconds, 2.0);
}

}  // namespace
}  // namespace ocp::scenario
