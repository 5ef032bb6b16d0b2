#pragma once
// The part of main() both simulator executables share: start the simulation (a start error,
// such as a busy port, is printed with a hint and gives exit code 1), then log its status
// line once a second until shutdown, log a summary at shutdown, and return the exit code.
#include <functional>
#include <memory>
#include <iostream>
#include <string>
#include <string_view>
#include <system_error>

#include "ocp/log.hpp"
#include "sim_app/common_options.hpp"
#include "sim_app/console.hpp"
#include "ocp/exit_codes.hpp"
#include "sim_app/real_time_runner.hpp"
#include "sim_app/wire_log.hpp"

namespace ocp::sim_app {

// `Simulation` needs start() → Status, stop(), status_line() → std::string, world() → World&.
// A start error names the option that moves a busy port (port_hint.hpp, where the port opens).
template <class Simulation>
[[nodiscard]] int run_simulation(std::string_view program,
                                 const CommonOptions& common, RealTimeRunner& runner,
                                 const Logger& logger, Simulation& simulation,
                                 std::function<std::string()> summary) {
  runner.set_logger(&logger);
  std::unique_ptr<WireLog> wire_log;   // subscribed before start: it sees the first frame
  if (!common.wire_log_path.empty()) {
    auto opened = WireLog::open(common.wire_log_path, simulation.world().events(), logger);
    if (!opened) {
      std::cerr << program << ": --wire-log: " << opened.error().detail << "\n";
      return cli::exit_usage_error;
    }
    wire_log = std::move(*opened);
  }
  if (auto status = simulation.start(); !status) {
    std::cerr << program << ": cannot start: " << status.error().detail << "\n";
    return cli::exit_usage_error;   // a busy port: the setup needs a change, as with a bad option
  }
  StatusTicker status(runner.executor(), Millis{1000},
                      [&] { logger.info("{}", simulation.status_line()); });
  status.start();
  runner.set_on_shutdown([&](const std::string&) {
    status.stop();
    logger.info("summary: {}", summary());
    simulation.stop();
  });
  return runner.run(common.duration());
}

}  // namespace ocp::sim_app
