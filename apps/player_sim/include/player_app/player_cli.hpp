#pragma once
// The command line of `player_sim`: the shared simulator options (sim_app/common_options.hpp)
// plus --vehicle (repeatable), --frame-rate-hz, --vehicle-tcp and the web view options. A function of its own so tests parse
// exactly what the executable parses.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "player_app/player_simulation.hpp"
#include "sim_app/common_options.hpp"
#include "sim_app/udp_com.hpp"

namespace ocp {

struct PlayerCli {
  sim_app::CommonOptions common;
  std::vector<std::string> vehicles;  // empty on the command line: one named "vehicle"
  double frame_rate_hz = 100.0;
  std::vector<std::string> vehicle_tcp_texts;       // NAME=PORT, checked into vehicle_tcp_ports
  std::map<std::string, std::uint16_t> vehicle_tcp_ports;
  int webview_port = 4002;
  std::string webview_root;                         // default: share/ocp-sim/web (sim_app/data_dir.hpp)
  bool no_webview = false;
  std::vector<std::string> webview_allowed_origins;   // --webview-allow-origin, normalised
  sim_app::ComOptions com;
  std::map<std::string, boost::asio::ip::udp::endpoint> udp_vehicles;   // from --vehicle NAME=udp://HOST:PORT

  PlayerSimOptions simulation_options() const;
};

// nullopt: run. Otherwise exit with the code (0 after --help, 2 on a usage error, printed to
// stderr with the "player_sim: " prefix).
[[nodiscard]] std::optional<int> parse_player_cli(int argc, const char* const* argv, PlayerCli& cli);

}  // namespace ocp
