// ocp_bench: measurement tools that drive the real cores and observe them through their event
// streams. Subcommands: loop (a vehicle client against a Streamer), fleet (the scale curve). Exit codes
// (ocp/exit_codes.hpp): 0 done, 1 a gate failed, 2 usage or harness error (a busy port), 130 Ctrl-C.
#include <CLI/CLI.hpp>
#include <iostream>

#include "fleet_command.hpp"
#include "loop_command.hpp"
#include "ocp/cli_parse.hpp"

int main(int argc, char** argv) {
  using namespace ocp::bench;
  CLI::App app{"OCP benchmarks on real sockets and in virtual time", "ocp_bench"};
  app.require_subcommand(1);
  LoopOptions loop_options;
  CLI::App* loop = add_loop_command(app, loop_options);
  FleetOptions fleet_options;
  CLI::App* fleet = add_fleet_command(app, fleet_options);
  if (auto exit_code = ocp::cli::parse_or_exit_code(app, argc, argv)) return *exit_code;
  if (loop->parsed()) return run_loop(loop_options);
  if (fleet->parsed()) return run_fleet(fleet_options);
  return 2;
}
