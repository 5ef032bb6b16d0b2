// player_sim: a Player on 127.0.0.1:4001 (ocp_player_tcp_port) linked to in-process simulated
// vehicles, for developing operator-side clients and dashboards.
// Exit codes: 0 normal end, 1 runtime error (port in use), 2 usage error.
#include "player_app/player_cli.hpp"
#include "player_app/player_simulation.hpp"
#include "sim_app/console.hpp"
#include "sim_app/run_simulation.hpp"

int main(int argc, char** argv) {
  using namespace ocp;
  PlayerCli cli;
  if (const auto exit_code = parse_player_cli(argc, argv, cli)) return *exit_code;

  const LogSink sink = make_console_sink(cli.common.log_level);
  sim_app::RealTimeRunner runner;   // first: the io_context outlives every socket below
  const Logger logger(runner.executor(), "player_sim", sink);
  PlayerSimulation simulation(runner.executor(), cli.simulation_options(), sink);
  return sim_app::run_simulation("player_sim", cli.common, runner, logger, simulation, [&] {
    const PlayerStats& stats = simulation.player().stats();
    return fmt::format("{} frames, {} feedback objects to the client, {} client messages, {} clients accepted, {} refused",
                       stats.frames, stats.client_frames_sent, stats.client_messages_received,
                       stats.client_connections_accepted, stats.client_connections_refused);
  });
}
