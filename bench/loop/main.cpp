// ocp_bench: measurement tools that drive the real cores and observe them through their event
// streams. Subcommands: loop (a vehicle client against a Streamer), fleet (the scale curve). Exit codes: 0 done,
// 1 runtime error, 2 usage error.
#include <CLI/CLI.hpp>
#include <iostream>

#include "fleet_command.hpp"
#include "loop_command.hpp"

int main(int argc, char** argv) {
  using namespace ocp::bench;
  CLI::App app{"OCP benchmarks on real sockets and in virtual time", "ocp_bench"};
  app.require_subcommand(1);
  LoopOptions loop_options;
  CLI::App* loop = add_loop_command(app, loop_options);
  FleetOptions fleet_options;
  CLI::App* fleet = add_fleet_command(app, fleet_options);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& help) {
    return app.exit(help);
  } catch (const CLI::CallForAllHelp& help) {
    return app.exit(help);
  } catch (const CLI::ParseError& error) {
    std::cerr << "ocp_bench: " << error.what() << "\nRun with --help for the options.\n";
    return 2;
  }
  if (loop->parsed()) return run_loop(loop_options);
  if (fleet->parsed()) return run_fleet(fleet_options);
  return 2;
}
