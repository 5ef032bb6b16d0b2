#pragma once
// The command line of `player_sim`: the shared simulator options (sim_app/common_options.hpp)
// plus --vehicle (repeatable) and --frame-rate-hz. A function of its own so tests parse
// exactly what the executable parses.
#include <optional>
#include <string>
#include <vector>

#include "player_app/player_simulation.hpp"
#include "sim_app/common_options.hpp"

namespace ocp {

struct PlayerCli {
  sim::CommonOptions common;
  std::vector<std::string> vehicles;  // empty on the command line: one named "vehicle"
  double frame_rate_hz = 100.0;

  PlayerSimOptions simulation_options() const;
};

// nullopt: run. Otherwise exit with the code (0 after --help, 2 on a usage error, printed to
// stderr with the "player_sim: " prefix).
[[nodiscard]] std::optional<int> parse_player_cli(int argc, const char* const* argv, PlayerCli& cli);

}  // namespace ocp
