#pragma once
// One way for every executable to end a command line that does not parse: --help and --version
// print and exit 0; a bad option prints "<program>: <what is wrong>" (the unknown word with the
// nearest known one, cli_suggest.hpp, else what CLI11 found) and a hint, and exits 2.
#include <CLI/CLI.hpp>
#include <iostream>
#include <optional>

#include "ocp/build_info.hpp"
#include "ocp/cli_suggest.hpp"
#include "ocp/exit_codes.hpp"

namespace ocp::cli {

// --version: the version, the build's git describe, the compiler and the libraries (build_info.hpp).
inline void add_version_flag(CLI::App& app) {
  const std::string program = app.get_name().empty() ? std::string("ocp-sim") : app.get_name();
  app.set_version_flag("--version", [program] { return build_info::version_text(program); },
                       "Print the version, the build, the compiler and the libraries, and exit");
}

// nullopt: parsed, go on. Otherwise the exit code to return from main.
inline std::optional<int> parse_or_exit_code(CLI::App& app, int argc, const char* const* argv) {
  add_version_flag(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& help) {
    return app.exit(help);
  } catch (const CLI::CallForAllHelp& help) {
    return app.exit(help);
  } catch (const CLI::CallForVersion& version) {
    return app.exit(version);
  } catch (const CLI::ParseError& error) {
    // A typo makes CLI11 blame the words after it; name the typo itself when there is one.
    const std::optional<std::string> typo = unknown_word(app, argc, argv);
    std::cerr << app.get_name() << ": " << (typo ? *typo : std::string(error.what()))
              << "\nRun with --help for more information.\n";
    return exit_usage_error;
  }
  return std::nullopt;
}

}  // namespace ocp::cli
