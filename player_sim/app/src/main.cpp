// player_sim: a Player on 127.0.0.1:4001 (ocp_player_tcp_port) linked to in-process simulated
// vehicles, for developing operator-side clients and dashboards.
// Exit codes: 0 normal end, 1 runtime error (port in use), 2 usage error.
#include <CLI/CLI.hpp>
#include <iostream>
#include <set>

#include "player_app/player_simulation.hpp"
#include "player_app/vehicle_tcp_option.hpp"
#include "sim_app/common_options.hpp"
#include "sim_app/console.hpp"
#include "sim_app/exit_codes.hpp"
#include "sim_app/run_simulation.hpp"

int main(int argc, char** argv) {
  using namespace ocp;
  CLI::App app{
      "OCP Player simulator: serves the operator-side TCP API (SPEC §4) on 127.0.0.1:4001,\n"
      "linked through fake com channels to simulated vehicles (Streamer + reference vehicle\n"
      "client, in-process). Connect your operator-side client to it.",
      "player_sim"};
  sim::CommonOptions common;
  sim::add_common_options(app, common);
  std::vector<std::string> vehicles;
  double frame_rate_hz = 100.0;
  app.add_option("--vehicle", vehicles, "simulated vehicle name (repeatable; several form a fleet; default: vehicle)")
      ->group("Player");
  app.add_option("--frame-rate-hz", frame_rate_hz, "Player frame rate (capped at 100)")
      ->capture_default_str()->check(CLI::Range(1.0, 100.0))->group("Player");
  std::vector<std::string> vehicle_tcp_texts;
  app.add_option("--vehicle-tcp", vehicle_tcp_texts,
                 "NAME=PORT: that vehicle's Streamer serves the vehicle TCP API on 127.0.0.1:PORT for an external "
                 "vehicle client instead of the in-process one (repeatable; PORT 0 = a free port)")
      ->group("Player");
  int webview_port = 4002;
  std::string webview_root = OCP_WEBVIEW_DEFAULT_ROOT;
  bool no_webview = false;
  app.add_option("--webview-port", webview_port, "web view HTTP + WebSocket port (0 = a free port, logged)")
      ->capture_default_str()->check(CLI::Range(0, 65535))->group("Web view");
  app.add_option("--webview-root", webview_root, "folder of the web view's static files (default: the built-in dashboard)")
      ->capture_default_str()->check(CLI::ExistingDirectory)->group("Web view");
  app.add_flag("--no-webview", no_webview, "do not serve the web view")->group("Web view");
  if (const auto exit_code = sim::parse_command_line(app, argc, argv, common)) return *exit_code;

  if (vehicles.empty()) vehicles.push_back("vehicle");
  std::set<std::string> unique;
  for (const auto& name : vehicles) {
    if (name.empty() || !unique.insert(name).second) {
      std::cerr << "player_sim: --vehicle '" << name << "': names must be non-empty and unique\n";
      return sim::exit_usage_error;
    }
  }

  const auto vehicle_tcp_ports = parse_vehicle_tcp(vehicle_tcp_texts, vehicles);
  if (!vehicle_tcp_ports) {
    std::cerr << "player_sim: " << vehicle_tcp_ports.error().detail << "\n";
    return sim::exit_usage_error;
  }

  PlayerSimOptions options;
  options.vehicle_tcp_ports = *vehicle_tcp_ports;
  if (!no_webview) {
    WebviewOptions webview;   // allow_remote follows ocp_tcp_allow_remote (PlayerSimulation)
    webview.port = static_cast<std::uint16_t>(webview_port);
    webview.root = webview_root;
    options.webview = webview;
  }
  options.vehicles = vehicles;
  options.plugin_params = common.plugin_params;
  options.cameras = common.cameras;
  options.link = common.link_impairments();
  options.seed = common.seed;
  options.gamepad = common.gamepad;
  options.frame_rate_hz = frame_rate_hz;

  const LogSink sink = make_console_sink(common.log_level);
  sim::RealTimeRunner runner;   // first: the io_context outlives every socket below
  const Logger logger(runner.executor(), "player_sim", sink);
  PlayerSimulation simulation(runner.executor(), options, sink);
  return sim::run_simulation("player_sim", "ocp_player_tcp_port", common, runner, logger, simulation, [&] {
    const PlayerStats& stats = simulation.player().stats();
    return fmt::format("{} frames, {} feedback objects to the client, {} client messages, {} clients accepted, {} refused",
                       stats.frames, stats.client_frames_sent, stats.client_messages_received,
                       stats.client_connections_accepted, stats.client_connections_refused);
  });
}
