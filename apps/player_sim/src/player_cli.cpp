#include "player_app/player_cli.hpp"

#include <iostream>
#include <set>

#include "ocp/cli_checks.hpp"
#include "player_app/vehicle_tcp_option.hpp"
#include "player_app/webview_server.hpp"
#include "ocp/exit_codes.hpp"
#include "sim_app/data_dir.hpp"

namespace ocp {

PlayerSimOptions PlayerCli::simulation_options() const {
  PlayerSimOptions options;
  static_cast<sim_app::SimulatedWorldOptions&>(options) = common.world_options();
  options.vehicles = vehicles;
  options.frame_rate_hz = frame_rate_hz;
  options.vehicle_tcp_ports = vehicle_tcp_ports;
  options.udp_vehicles = udp_vehicles;
  options.com_key = com.key;
  if (!no_webview) {
    WebviewOptions webview;   // allow_remote follows ocp_tcp_allow_remote (PlayerSimulation)
    webview.port = static_cast<std::uint16_t>(webview_port);
    webview.root = webview_root;
    webview.allowed_origins = webview_allowed_origins;
    options.webview = webview;
  }
  return options;
}

namespace {

// The options player_sim adds to the common ones.
void add_player_options(CLI::App& app, PlayerCli& cli) {
  sim_app::add_common_options(app, cli.common);
  app.add_option("--vehicle", cli.vehicles, "simulated vehicle name (repeatable; several form a fleet; default: vehicle); NAME=udp://HOST:PORT: "
                 "that vehicle is a real Streamer (streamer_sim --com-listen HOST:PORT) over a UDP com channel")
      ->group("Player");
  app.add_option("--frame-rate-hz", cli.frame_rate_hz, "Player frame rate (capped at 100)")
      ->capture_default_str()->check(cli::real(1.0, 100.0))->group("Player");
  app.add_option("--vehicle-tcp", cli.vehicle_tcp_texts,
                 "NAME=PORT: that vehicle's Streamer serves the vehicle TCP API on 127.0.0.1:PORT for an external "
                 "vehicle client instead of the in-process one (repeatable; PORT 0 = a free port)")
      ->group("Player");
  app.add_option("--webview-port", cli.webview_port, "web view HTTP + WebSocket port (0 = a free port, logged)")
      ->capture_default_str()->check(CLI::Range(0, 65535))->group("Web view");
  app.add_option("--webview-root", cli.webview_root, "folder of the web view's static files (default: the dashboard in the data folder, share/ocp-sim/web; "
                 "OCP_SIM_DATA overrides)")
      ->capture_default_str()->check(CLI::ExistingDirectory)->group("Web view");
  app.add_flag("--no-webview", cli.no_webview, "do not serve the web view")->group("Web view");
  app.add_option("--webview-allow-origin", cli.webview_allowed_origins,
                 "ORIGIN (scheme://host[:port], e.g. http://localhost:8080): pages served from it may use the web "
                 "view too (repeatable; by default only the web view's own pages may)")
      ->check(CLI::Validator(
          [](std::string& text) {
            auto origin = parse_webview_origin(text);
            if (!origin) return origin.error().detail;
            text = *origin;
            return std::string();
          },
          "ORIGIN"))
      ->group("Web view");
  sim_app::add_com_options(app, cli.com);
}

// After parsing: the vehicle names (NAME=udp://… split off), their --vehicle-tcp ports and
// UDP Streamers, each checked; an exit code when one is wrong.
std::optional<int> complete_vehicles(PlayerCli& cli) {
  std::map<std::string, std::string> udp_texts;
  for (auto& text : cli.vehicles) {
    const std::size_t scheme = text.find("=udp://");
    if (scheme == std::string::npos) continue;
    udp_texts[text.substr(0, scheme)] = text.substr(scheme + 7);
    text = text.substr(0, scheme);
  }

  if (cli.vehicles.empty()) cli.vehicles.push_back("vehicle");
  std::set<std::string> unique;
  for (const auto& name : cli.vehicles) {
    if (name.empty() || !unique.insert(name).second) {
      std::cerr << "player_sim: --vehicle '" << name << "': names must be non-empty and unique\n";
      return cli::exit_usage_error;
    }
  }
  const auto vehicle_tcp_ports = parse_vehicle_tcp(cli.vehicle_tcp_texts, cli.vehicles);
  if (!vehicle_tcp_ports) {
    std::cerr << "player_sim: " << vehicle_tcp_ports.error().detail << "\n";
    return cli::exit_usage_error;
  }
  cli.vehicle_tcp_ports = *vehicle_tcp_ports;
  if (udp_texts.empty() && (!cli.com.key_file.empty() || cli.com.insecure || cli.com.allow_remote)) {
    std::cerr << "player_sim: --com-key, --com-insecure and --com-allow-remote need --vehicle NAME=udp://HOST:PORT\n";
    return cli::exit_usage_error;
  }
  for (const auto& [name, text] : udp_texts) {
    auto endpoint = sim_app::resolve_udp_endpoint(text, false);
    if (!endpoint) {
      std::cerr << "player_sim: --vehicle " << name << "=udp://" << endpoint.error().detail << "\n";
      return cli::exit_usage_error;
    }
    if (cli.vehicle_tcp_ports.contains(name)) {
      std::cerr << "player_sim: vehicle '" << name << "' is a real Streamer over UDP: it has no --vehicle-tcp\n";
      return cli::exit_usage_error;
    }
    if (auto checked = sim_app::check_com_options(cli.com, *endpoint, false); !checked) {
      std::cerr << "player_sim: " << checked.error().detail << "\n";
      return cli::exit_usage_error;
    }
    cli.udp_vehicles[name] = *endpoint;
  }
  return std::nullopt;
}

// Without --webview-root, the dashboard of the data folder (sim_app/data_dir.hpp): an exit 2
// that says where it looked when it is missing, never an empty page.
std::optional<int> complete_webview_root(PlayerCli& cli) {
  if (cli.no_webview || !cli.webview_root.empty()) return std::nullopt;
  try {
    cli.webview_root = sim_app::find_data("web/index.html").parent_path().string();
  } catch (const sim_app::DataNotFound& missing) {
    std::cerr << "player_sim: the web view's files: " << missing.what() << " (or give --webview-root, or --no-webview)\n";
    return cli::exit_usage_error;
  }
  return std::nullopt;
}

}  // namespace

std::optional<int> parse_player_cli(int argc, const char* const* argv, PlayerCli& cli) {
  CLI::App app{
      "OCP Player simulator: serves the operator-side TCP API (SPEC §4) on 127.0.0.1:4001,\n"
      "linked through fake com channels to simulated vehicles (Streamer + reference vehicle\n"
      "client, in-process). Connect your operator-side client to it.",
      "player_sim"};
  add_player_options(app, cli);
  if (auto exit_code = sim_app::parse_command_line(app, argc, argv, cli.common)) return exit_code;
  if (auto exit_code = complete_vehicles(cli)) return exit_code;
  return complete_webview_root(cli);
}

}  // namespace ocp
