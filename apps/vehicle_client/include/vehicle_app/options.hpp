#pragma once
// Command line of the vehicle_client program: `vehicle_client [host:port] [options]`.
#include <optional>
#include <string>

#include "ocp/log.hpp"
#include "vehicle_app/tcp_runner.hpp"
#include "vehicle_client/vehicle_client.hpp"

namespace ocp {

struct ProgramOptions {
  VehicleClientConfig client;
  TcpRunnerConfig runner;
  LogLevel log_level = LogLevel::info;
  std::optional<double> duration_s;  // run this long, then exit 0 (demos, tests)
  bool status_line = true;
};

// Parses argv. Returns the options, or an exit code: 0 after --help, 2 for bad options (the
// message has been printed to stderr).
struct ParseOutcome {
  std::optional<ProgramOptions> options;
  int exit_code = 0;
};
ParseOutcome parse_program_options(int argc, const char* const* argv);

}  // namespace ocp
