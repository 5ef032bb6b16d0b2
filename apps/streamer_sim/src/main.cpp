// streamer_sim: a Streamer on 127.0.0.1:4000 (tcp_port) with an in-process simulated operator
// behind a fake com channel, for developing a vehicle integration without Oden at hand.
// Exit codes: 0 normal end, 1 runtime error (port in use), 2 usage error.
#include "sim_app/console.hpp"
#include "sim_app/run_simulation.hpp"
#include "streamer_app/streamer_cli.hpp"
#include "streamer_app/streamer_simulation.hpp"

int main(int argc, char** argv) {
  using namespace ocp;
  StreamerCli cli;
  if (const auto exit_code = parse_streamer_cli(argc, argv, cli)) return *exit_code;

  const LogSink sink = make_console_sink(cli.common.log_level);
  sim_app::RealTimeRunner runner;   // first: the io_context outlives every socket below
  const Logger logger(runner.executor(), "streamer_sim", sink);
  StreamerSimulation simulation(runner.executor(), cli.simulation_options(), sink);
  return sim_app::run_simulation("streamer_sim", cli.common, runner, logger, simulation, [&] {
    const StreamerStats& stats = simulation.streamer().stats();
    return fmt::format("{} control frames sent, {} vehicle responses (keep-alives included), {} connections accepted, {} refused",
                       stats.control_frames_sent, stats.vehicle_responses_received,
                       stats.connections_accepted, stats.connections_refused);
  });
}
