#pragma once
// The command line of `streamer_sim`: the shared simulator options (sim_app/common_options.hpp)
// plus --vehicle and --operator-rate-hz. A function of its own so tests parse exactly what the
// executable parses.
#include <optional>
#include <string>

#include "sim_app/common_options.hpp"
#include "sim_app/udp_com.hpp"
#include "streamer_app/streamer_simulation.hpp"

namespace ocp {

struct StreamerCli {
  sim_app::CommonOptions common;
  std::string vehicle = "vehicle";
  double operator_rate_hz = 100.0;
  std::string com_listen;          // ADDR:PORT; empty: the simulated operator
  sim_app::ComOptions com;
  std::optional<boost::asio::ip::udp::endpoint> com_endpoint;   // com_listen, resolved

  StreamerSimOptions simulation_options() const;
};

// nullopt: run. Otherwise exit with the code (0 after --help, 2 on a usage error, printed to
// stderr with the "streamer_sim: " prefix).
[[nodiscard]] std::optional<int> parse_streamer_cli(int argc, const char* const* argv, StreamerCli& cli);

}  // namespace ocp
