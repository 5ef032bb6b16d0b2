#include "streamer_app/streamer_cli.hpp"

#include <iostream>

#include "ocp/cli_checks.hpp"
#include "ocp/exit_codes.hpp"

namespace ocp {

StreamerSimOptions StreamerCli::simulation_options() const {
  StreamerSimOptions options;
  static_cast<sim_app::SimulatedWorldOptions&>(options) = common.world_options();
  options.vehicle = vehicle;
  options.operator_frame_rate_hz = operator_rate_hz;
  options.com_listen = com_endpoint;
  options.com_key = com.key;
  return options;
}

std::optional<int> parse_streamer_cli(int argc, const char* const* argv, StreamerCli& cli) {
  CLI::App app{
      "OCP Streamer simulator: serves the vehicle-side TCP API (SPEC §3) on 127.0.0.1:4000 and\n"
      "drives it from a simulated operator (scripted gamepad, self-echo) behind a fake com\n"
      "channel. Connect your vehicle client (or the reference `vehicle_client`) to it.",
      "streamer_sim"};
  sim_app::add_common_options(app, cli.common);
  app.add_option("--vehicle", cli.vehicle, "vehicle (Streamer) name")->capture_default_str()->group("Streamer");
  app.add_option("--operator-rate-hz", cli.operator_rate_hz, "operator control message rate (capped at 100)")
      ->capture_default_str()->check(cli::real(1.0, 100.0))->group("Simulated operator");
  app.add_option("--com-listen", cli.com_listen,
                 "ADDR:PORT: the operator is a real Player (player_sim --vehicle NAME=udp://ADDR:PORT) over a UDP com "
                 "channel on this address, instead of the simulated one (needs --com-key FILE or, on loopback, "
                 "--com-insecure)")
      ->group("Com channel over UDP");
  sim_app::add_com_options(app, cli.com);
  if (auto exit_code = sim_app::parse_command_line(app, argc, argv, cli.common)) return exit_code;
  if (cli.vehicle.empty()) {
    std::cerr << "streamer_sim: --vehicle must not be empty\n";
    return cli::exit_usage_error;
  }
  if (cli.com_listen.empty()) {
    if (!cli.com.key_file.empty() || cli.com.insecure || cli.com.allow_remote) {
      std::cerr << "streamer_sim: --com-key, --com-insecure and --com-allow-remote need --com-listen ADDR:PORT\n";
      return cli::exit_usage_error;
    }
    return std::nullopt;
  }
  auto endpoint = sim_app::resolve_udp_endpoint(cli.com_listen, true);
  if (!endpoint) {
    std::cerr << "streamer_sim: --com-listen " << endpoint.error().detail << "\n";
    return cli::exit_usage_error;
  }
  if (auto checked = sim_app::check_com_options(cli.com, *endpoint, true); !checked) {
    std::cerr << "streamer_sim: " << checked.error().detail << "\n";
    return cli::exit_usage_error;
  }
  cli.com_endpoint = *endpoint;
  return std::nullopt;
}

}  // namespace ocp
