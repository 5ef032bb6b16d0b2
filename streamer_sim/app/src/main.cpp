// streamer_sim: a Streamer on 127.0.0.1:4000 (tcp_port) with an in-process simulated operator
// behind a fake com channel, for developing a vehicle integration without Oden at hand.
// Exit codes: 0 normal end, 1 runtime error (port in use), 2 usage error.
#include <CLI/CLI.hpp>
#include <iostream>

#include "sim_common/common_options.hpp"
#include "sim_common/console.hpp"
#include "sim_common/exit_codes.hpp"
#include "sim_common/gamepad_script.hpp"
#include "sim_common/real_time_runner.hpp"
#include "streamer_app/streamer_simulation.hpp"

int main(int argc, char** argv) {
  using namespace ocp;
  CLI::App app{
      "OCP Streamer simulator: serves the vehicle-side TCP API (SPEC §3) on 127.0.0.1:4000 and\n"
      "drives it from a simulated operator (scripted gamepad, self-echo) behind a fake com\n"
      "channel. Connect your vehicle client (or the reference `vehicle_client`) to it.",
      "streamer_sim"};
  sim::CommonOptions common;
  sim::add_common_options(app, common);
  std::string vehicle = "vehicle";
  std::string gamepad_text = "drive";
  double operator_rate_hz = 100.0;
  app.add_option("--vehicle", vehicle, "vehicle (Streamer) name")->capture_default_str()->group("Streamer");
  app.add_option("--gamepad", gamepad_text, "operator gamepad: idle, drive, or a recording file")
      ->capture_default_str()->group("Simulated operator");
  app.add_option("--operator-rate-hz", operator_rate_hz, "operator control message rate (capped at 100)")
      ->capture_default_str()->check(CLI::Range(1.0, 100.0))->group("Simulated operator");
  if (const auto exit_code = sim::parse_command_line(app, argc, argv, common)) return *exit_code;

  auto gamepad = sim::parse_gamepad_script(gamepad_text);
  if (!gamepad) {
    std::cerr << "streamer_sim: " << gamepad.error().detail << "\nRun with --help for the options.\n";
    return sim::exit_usage_error;
  }
  if (vehicle.empty()) {
    std::cerr << "streamer_sim: --vehicle must not be empty\n";
    return sim::exit_usage_error;
  }

  StreamerSimOptions options;
  options.vehicle = vehicle;
  options.plugin_params = common.plugin_params;
  for (const auto& camera : common.cameras) {
    CameraConfig config;
    config.name = camera.name;
    config.fps = camera.fps;
    options.cameras.push_back(config);
  }
  options.link = common.link_impairments();
  options.seed = common.seed;
  options.gamepad = std::move(*gamepad);
  options.operator_frame_rate_hz = operator_rate_hz;

  const LogSink sink = sim::configure_console(common.log_level);
  sim::RealTimeRunner runner;   // first: the io_context outlives every socket below
  const Logger logger(runner.executor(), "streamer_sim", sink);
  runner.set_logger(&logger);
  StreamerSimulation simulation(runner.executor(), options, sink);
  if (auto status = simulation.start(); !status) {
    std::cerr << "streamer_sim: cannot start: " << status.error().detail;
    if (status.error().code == std::errc::address_in_use) {
      std::cerr << " (is another streamer_sim running? pick a port with --plugin-param tcp_port N)";
    }
    std::cerr << "\n";
    return sim::exit_runtime_error;
  }
  sim::StatusTicker status(runner.executor(), Millis{1000}, [&] { logger.info("{}", simulation.status_line()); });
  status.start();
  runner.set_on_shutdown([&](const std::string&) {
    status.stop();
    const StreamerStats& stats = simulation.streamer().stats();
    logger.info("summary: {} control frames sent, {} vehicle responses, {} connections accepted, {} refused",
                stats.control_frames_sent, stats.vehicle_responses_received, stats.connections_accepted,
                stats.connections_refused);
    simulation.stop();
  });
  return runner.run(common.duration());
}
