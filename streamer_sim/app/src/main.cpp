// streamer_sim: a Streamer on 127.0.0.1:4000 (tcp_port) with an in-process simulated operator
// behind a fake com channel, for developing a vehicle integration without Oden at hand.
// Exit codes: 0 normal end, 1 runtime error (port in use), 2 usage error.
#include <CLI/CLI.hpp>
#include <iostream>

#include "sim_app/common_options.hpp"
#include "sim_app/console.hpp"
#include "sim_app/exit_codes.hpp"
#include "sim_app/run_simulation.hpp"
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
  double operator_rate_hz = 100.0;
  app.add_option("--vehicle", vehicle, "vehicle (Streamer) name")->capture_default_str()->group("Streamer");
  app.add_option("--operator-rate-hz", operator_rate_hz, "operator control message rate (capped at 100)")
      ->capture_default_str()->check(CLI::Range(1.0, 100.0))->group("Simulated operator");
  if (const auto exit_code = sim::parse_command_line(app, argc, argv, common)) return *exit_code;

  if (vehicle.empty()) {
    std::cerr << "streamer_sim: --vehicle must not be empty\n";
    return sim::exit_usage_error;
  }

  StreamerSimOptions options;
  options.vehicle = vehicle;
  options.plugin_params = common.plugin_params;
  options.cameras = common.cameras;
  options.link = common.link_impairments();
  options.seed = common.seed;
  options.gamepad = common.gamepad;
  options.operator_frame_rate_hz = operator_rate_hz;

  const LogSink sink = make_console_sink(common.log_level);
  sim::RealTimeRunner runner;   // first: the io_context outlives every socket below
  const Logger logger(runner.executor(), "streamer_sim", sink);
  StreamerSimulation simulation(runner.executor(), options, sink);
  return sim::run_simulation("streamer_sim", "tcp_port", common, runner, logger, simulation, [&] {
    const StreamerStats& stats = simulation.streamer().stats();
    return fmt::format("{} control frames sent, {} vehicle responses, {} connections accepted, {} refused",
                       stats.control_frames_sent, stats.vehicle_responses_received,
                       stats.connections_accepted, stats.connections_refused);
  });
}
