// ocp_conformance: command line only; everything else is in the conformance library.
//   ocp_conformance vehicle|operator [options] [--time virtual|real] [-- CMD ARGS…]
// Exit codes: 0 every MUST case passed (or failed as the baseline expects), 1 a failure,
// 2 a harness error (bad options, port in use, client could not be launched), 130 Ctrl-C.
#include <CLI/CLI.hpp>
#include <stdlib.h>
#include <signal.h>

#include <filesystem>
#include <fstream>
#include <iostream>

#include "conformance/baseline.hpp"
#include "conformance/coverage.hpp"
#include "conformance/reports.hpp"
#include "conformance/requirements.hpp"
#include "conformance/runner.hpp"
#include "conformance/vehicle_cases.hpp"
#include "sim_app/client_process.hpp"
#include "ocp/cli_parse.hpp"
#include "ocp/cli_paths.hpp"
#include "ocp/cli_checks.hpp"
#include "ocp/interrupt.hpp"

namespace {

using namespace ocp::conformance;

bool write_file(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  return static_cast<bool>(out);
}

// The command line of either suite.
struct SuiteCommandLine {
  RunOptions options;
  int port = -1;
  double connect_timeout_s = 3.0;
  bool list = false, markdown = false, coverage = false, broken_clients = false;
  std::string include, exclude, out_dir, junit, baseline_path, write_baseline;
  // --time: virtual (the default with -- CMD) or real (the only one for a client started by hand)
  std::string time;
  std::vector<std::string> command;
};

// Both suites take the same options (CLI11 binds each subcommand's copy to one variable).
void add_suite_options(CLI::App& suite, bool is_vehicle, SuiteCommandLine& line) {
  RunOptions& options = line.options;
  suite
      .add_option(
          "--port", line.port,
          is_vehicle ? "Port to listen on (default: 4000 waiting for an external client; ephemeral when launching one)"
                     : "Port to listen on (default: 4001 waiting for an external client; ephemeral when launching one)")
      ->check(CLI::Range(0, 65535));
  suite.add_flag("--restart-per-case", options.restart_per_case, "Launch a fresh client for every case");
  suite
      .add_option("--jobs,-j", options.jobs,
                  "Cases run concurrently (launched clients only; one client and port per job)")
      ->check(CLI::Range(1, 16));
  CLI::Option* list = suite.add_flag("--list", line.list, "List the cases and exit");
  suite.add_flag("--markdown", line.markdown, "With --list: the Markdown table of docs/conformance.md")->needs(list);
  // One list at a time: without --list, or with another format, it is a usage error (exit 2).
  CLI::Option* coverage = suite
                              .add_flag("--coverage", line.coverage,
                                        "With --list: the Markdown coverage table, one row per client-side requirement "
                                        "(source, tier, cases, broken clients)")
                              ->needs(list);
  suite
      .add_flag("--broken-clients", line.broken_clients,
                "With --list: every broken client that must fail a case, one a line: id, tier, verdict, cases, client "
                "(tab-separated)")
      ->needs(list)
      ->excludes(coverage);
  suite.add_option("--cases", line.include,
                   "Only these cases: comma-separated ids, prefixes or globs (vehicle/2,vehicle/3.3/*)");
  suite.add_option("--exclude", line.exclude, "Skip these cases (same syntax)");
  suite.add_option("--timeout-scale", options.timeout_scale, "Multiply every timeout (slow machines, sanitizers)")
      ->check(ocp::cli::real(0.1, 100.0));
  suite
      .add_option("--connect-timeout-s", line.connect_timeout_s,
                  "A launched client that has not connected this long after its launch (or exited before) stops the "
                  "run: exit 2")
      ->capture_default_str()
      ->check(ocp::cli::real(0.1, 600.0));
  suite.add_option("--out", line.out_dir, "Write index.json, report.html and client logs into this directory")
      ->check(ocp::cli::writable_folder());
  suite.add_option("--junit", line.junit, "Write JUnit XML to this file")->check(ocp::cli::writable_file());
  suite.add_option("--baseline", line.baseline_path,
                   "Expected failures (one case id per line); the run is judged against it");
  suite.add_option("--write-baseline", line.write_baseline, "Write this run's failures as a baseline file");
  suite.add_option("command", line.command, "-- CMD ARGS…: launch the client; OCP_PORT and {port} carry the port");
  suite
      .add_option("--time", line.time,
                  "virtual (the default with -- CMD: the client runs on the suite's clock through a preloaded shim, "
                  "every case's timing exact, the suite in seconds; a static binary or Go cannot: exit 2 and use "
                  "--time real; docs/virtual-time.md) or real (wall-clock cases; the default, and the only choice, "
                  "without -- CMD: a client you start by hand)")
      ->check(CLI::IsMember({"real", "virtual"}));
  if (is_vehicle) {
    // A client whose interlock works other buttons than the reference client's is judged on
    // the §10 cases when it says which (docs/protocol.md §10), instead of "not judged".
    const std::vector<std::string> buttons(controller_buttons.begin(), controller_buttons.end());
    suite
        .add_option(
            "--enable-button", options.interlock.enable,
            "The gamepad button that enables your drive interlock (pressed with the sticks at rest), for the §10 cases")
        ->capture_default_str()
        ->check(CLI::IsMember(buttons))
        ->group("Safety (SPEC §10)");
    suite
        .add_option("--stop-button", options.interlock.stop,
                    "The gamepad button of your emergency stop, for vehicle/10/3")
        ->capture_default_str()
        ->check(CLI::IsMember(buttons))
        ->group("Safety (SPEC §10)");
  }
}

void print_case_list(const std::vector<VehicleCase>& cases, const SuiteCommandLine& line, bool operator_suite) {
  std::vector<CaseInfo> infos;
  for (const auto& c : cases) infos.push_back(c.body.info);
  if (line.coverage) {
    std::cout << requirement_table(operator_suite ? operator_requirements() : vehicle_requirements(), infos);
  } else if (line.broken_clients) {
    std::cout << broken_client_lines(infos);
  } else {
    std::cout << case_list(infos, line.markdown);
  }
}

// Without --out, a launched client's output still goes to a file, so that a client that fails
// to start can be shown by its last lines; the folder is removed when the run ends.
class TemporaryLogFolder {
 public:
  ~TemporaryLogFolder() {
    std::error_code ignored;
    if (!path_.empty()) std::filesystem::remove_all(path_, ignored);
  }
  std::string make() {
    std::string pattern = (std::filesystem::temp_directory_path() / "ocp_conformance_clients_XXXXXX").string();
    if (::mkdtemp(pattern.data()) != nullptr) path_ = pattern;
    return path_;
  }

 private:
  std::string path_;
};

// The rest of the run options: the port (well-known when waiting for an external client, any
// free one when launching it) and the client logs' folder (under --out, or a temporary one).
// False (said why): --out cannot be made, or --time virtual cannot be had.
bool complete_run_options(SuiteCommandLine& line, bool operator_suite, TemporaryLogFolder& temporary_logs) {
  RunOptions& options = line.options;
  options.command = line.command;
  if (line.time.empty()) line.time = line.command.empty() ? "real" : "virtual";
  if (line.time == "virtual") {
    if (line.command.empty()) {
      std::cerr << "ocp_conformance: --time virtual launches the client: give it as -- CMD ARGS…\n";
      return false;
    }
    options.virtual_time = true;
    options.controller.shim_path = ocp::vtime::find_shim();
    if (options.controller.shim_path.empty()) {
      std::cerr << "ocp_conformance: --time virtual needs the shim libocp_vtime_shim.so (beside the program in ../lib, "
                   "or in $OCP_VTIME_SHIM); use --time real\n";
      return false;
    }
  }
  options.connect_timeout = std::chrono::milliseconds(static_cast<std::int64_t>(line.connect_timeout_s * 1000.0));
  options.port = static_cast<std::uint16_t>(
      line.port >= 0 ? line.port : (line.command.empty() ? (operator_suite ? 4001 : 4000) : 0));
  if (line.out_dir.empty()) {
    if (!line.command.empty()) options.client_log_dir = temporary_logs.make();
    options.client_logs_kept = false;
    return true;
  }
  std::error_code error;
  std::filesystem::create_directories(line.out_dir + "/clients", error);
  if (error) {
    std::cerr << "ocp_conformance: cannot create " << line.out_dir << ": " << error.message() << "\n";
    return false;
  }
  options.client_log_dir = line.out_dir + "/clients";
  return true;
}

// The launched command, or where an external client is expected.
std::string client_description(const SuiteCommandLine& line) {
  std::string client = "external client on 127.0.0.1:" + std::to_string(line.options.port);
  if (!line.command.empty()) {
    client.clear();
    for (const auto& word : line.command) client += (client.empty() ? "" : " ") + word;
  }
  return client;
}

// --out's index.json and report.html, --junit and --write-baseline; false when one failed
// (each is still tried).
bool write_reports(const SuiteCommandLine& line, const ReportContext& context, const RunSummary& summary) {
  bool wrote = true;
  if (!line.out_dir.empty()) {
    wrote = write_file(line.out_dir + "/index.json", index_json(context)) &&
            write_file(line.out_dir + "/report.html", html_report(context));
    std::cout << "Reports: " << line.out_dir << "/index.json, " << line.out_dir << "/report.html\n";
  }
  if (!line.junit.empty()) wrote = write_file(line.junit, junit_xml(context)) && wrote;
  if (!line.write_baseline.empty()) wrote = write_file(line.write_baseline, baseline_text(summary.results)) && wrote;
  return wrote;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"OCP conformance suite: plays one side of an OCP TCP API against a client under test.",
               "ocp_conformance"};
  app.require_subcommand(1);
  CLI::App* vehicle =
      app.add_subcommand("vehicle", "Play the Streamer (vehicle-side API, SPEC §2/§3/§5) against a vehicle client");
  CLI::App* operator_side =
      app.add_subcommand("operator",
                         "Play the Player (operator-side :4001 API, SPEC §4) against an operator client; a real "
                         "Streamer and the reference vehicle client run behind it");
  SuiteCommandLine line;
  for (CLI::App* suite : {vehicle, operator_side}) add_suite_options(*suite, suite == vehicle, line);

  if (auto exit_code = ocp::cli::parse_or_exit_code(app, argc, argv)) return *exit_code;
  const bool operator_suite = operator_side->parsed();
  if (line.options.interlock.enable == line.options.interlock.stop) {
    std::cerr << "ocp_conformance: --enable-button and --stop-button are both '" << line.options.interlock.enable
              << "': an interlock needs two buttons\nRun with --help for more information.\n";
    return 2;
  }
  const std::string suite_name = operator_suite ? "operator" : "vehicle";
  std::vector<VehicleCase> cases =
      select_cases(operator_suite ? operator_cases() : vehicle_cases(), line.include, line.exclude);
  if (line.list) {
    print_case_list(cases, line, operator_suite);
    return 0;
  }
  if (cases.empty()) {
    std::cerr << "ocp_conformance: no case matches\n";
    return 2;
  }
  std::optional<Baseline> baseline;
  if (!line.baseline_path.empty()) {
    auto loaded = load_baseline(line.baseline_path);
    if (!loaded) {
      std::cerr << "ocp_conformance: " << loaded.error().detail << "\n";
      return 2;
    }
    baseline = *loaded;
  }
  TemporaryLogFolder temporary_logs;
  if (!complete_run_options(line, operator_suite, temporary_logs)) return 2;
  // Ctrl-C stops the run after the finished cases are reported; a second one ends it at once,
  // killing the launched clients first (async-signal-safe), so they never outlive us.
  ocp::cli::install_interrupt_handlers(ocp::sim_app::kill_all_clients);
  line.options.stop_requested = ocp::cli::interrupt_requested;
  signal(SIGPIPE, SIG_IGN);

  const std::string client = client_description(line);
  std::cout << "ocp_conformance " << suite_name << ": " << cases.size() << " cases against " << client
            << (line.options.virtual_time ? " in virtual time" : "") << "\n";
  if (line.command.empty())
    std::cout << "waiting for the client to connect to 127.0.0.1:" << line.options.port << " …\n";
  line.options.on_result = [](const CaseResult& r) {
    print_case_line(std::cout, r);
    std::cout.flush();
  };
  const RunSummary summary = run_cases(cases, line.options);

  std::optional<BaselineDiff> diff;
  if (baseline) diff = diff_baseline(*baseline, summary.results);
  ReportContext context{suite_name, client, &summary, diff ? &*diff : nullptr};
  print_summary(std::cout, context);
  if (!write_reports(line, context, summary)) {
    std::cerr << "ocp_conformance: could not write a report\n";
    return 2;
  }
  return run_exit_code(summary, baseline ? &*baseline : nullptr);
}
