#pragma once
// One way for every executable to end a command line that does not parse: --help prints and
// exits 0; a bad option prints "<program>: <what CLI11 found>" and a hint, and exits 2.
#include <CLI/CLI.hpp>
#include <iostream>
#include <optional>

#include "ocp/exit_codes.hpp"

namespace ocp::cli {

// nullopt: parsed, go on. Otherwise the exit code to return from main.
inline std::optional<int> parse_or_exit_code(CLI::App& app, int argc, const char* const* argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& help) {
    return app.exit(help);
  } catch (const CLI::CallForAllHelp& help) {
    return app.exit(help);
  } catch (const CLI::ParseError& error) {
    std::cerr << app.get_name() << ": " << error.what() << "\nRun with --help for more information.\n";
    return exit_usage_error;
  }
  return std::nullopt;
}

}  // namespace ocp::cli
