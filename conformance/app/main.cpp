// ocp_conformance: command line only; everything else is in the conformance library.
//   ocp_conformance vehicle|operator [options] [-- CMD ARGS…]
// Exit codes: 0 every MUST case passed (or failed as the baseline expects), 1 a failure,
// 2 a harness error (bad options, port in use, client could not be launched).
#include <CLI/CLI.hpp>
#include <signal.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iostream>

#include "conformance/baseline.hpp"
#include "conformance/client_launcher.hpp"
#include "conformance/reports.hpp"
#include "conformance/runner.hpp"
#include "conformance/vehicle_cases.hpp"
#include "ocp/cli_parse.hpp"
#include "ocp/cli_checks.hpp"

namespace {

using namespace ocp::conformance;

extern "C" void on_signal(int signal_number) {
  kill_all_clients();   // async-signal-safe: the children never outlive us
  _exit(128 + signal_number);
}

bool write_file(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  return static_cast<bool>(out);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"OCP conformance suite: plays one side of an OCP TCP API against a client under test.", "ocp_conformance"};
  app.require_subcommand(1);
  CLI::App* vehicle = app.add_subcommand("vehicle", "Play the Streamer (vehicle-side API, SPEC §2/§3/§5) against a vehicle client");
  CLI::App* operator_side = app.add_subcommand(
      "operator", "Play the Player (operator-side :4001 API, SPEC §4) against an operator client; a real Streamer and the reference vehicle client run behind it");

  RunOptions options;
  int port = -1;
  bool list = false, markdown = false;
  std::string include, exclude, out_dir, junit, baseline_path, write_baseline;
  std::vector<std::string> command;
  // Both suites take the same options (CLI11 binds each subcommand's copy to one variable).
  for (CLI::App* suite : {vehicle, operator_side}) {
    const bool is_vehicle = suite == vehicle;
    suite->add_option("--port", port, is_vehicle ? "Port to listen on (default: 4000 waiting for an external client; ephemeral when launching one)"
                                                 : "Port to listen on (default: 4001 waiting for an external client; ephemeral when launching one)")
        ->check(CLI::Range(0, 65535));
    suite->add_flag("--restart-per-case", options.restart_per_case, "Launch a fresh client for every case");
    suite->add_option("--jobs,-j", options.jobs, "Cases run concurrently (launched clients only; one client and port per job)")
        ->check(CLI::Range(1, 16));
    suite->add_flag("--list", list, "List the cases and exit");
    suite->add_flag("--markdown", markdown, "With --list: the Markdown table of docs/conformance.md");
    suite->add_option("--cases", include, "Only these cases: comma-separated ids, prefixes or globs (vehicle/2,vehicle/3.3/*)");
    suite->add_option("--exclude", exclude, "Skip these cases (same syntax)");
    suite->add_option("--timeout-scale", options.timeout_scale, "Multiply every timeout (slow machines, sanitizers)")
        ->check(ocp::cli::real(0.1, 100.0));
    suite->add_option("--out", out_dir, "Write index.json, report.html and client logs into this directory");
    suite->add_option("--junit", junit, "Write JUnit XML to this file");
    suite->add_option("--baseline", baseline_path, "Expected failures (one case id per line); the run is judged against it");
    suite->add_option("--write-baseline", write_baseline, "Write this run's failures as a baseline file");
    suite->add_option("command", command, "-- CMD ARGS…: launch the client; OCP_PORT and {port} carry the port");
  }

  if (auto exit_code = ocp::cli::parse_or_exit_code(app, argc, argv)) return *exit_code;
  const bool operator_suite = operator_side->parsed();
  const std::string suite_name = operator_suite ? "operator" : "vehicle";
  std::vector<VehicleCase> cases = select_cases(operator_suite ? operator_cases() : vehicle_cases(), include, exclude);
  if (list) {
    std::vector<CaseInfo> infos;
    for (const auto& c : cases) infos.push_back(c.body.info);
    std::cout << case_list(infos, markdown);
    return 0;
  }
  if (cases.empty()) {
    std::cerr << "ocp_conformance: no case matches\n";
    return 2;
  }
  std::optional<Baseline> baseline;
  if (!baseline_path.empty()) {
    auto loaded = load_baseline(baseline_path);
    if (!loaded) {
      std::cerr << "ocp_conformance: " << loaded.error().detail << "\n";
      return 2;
    }
    baseline = *loaded;
  }
  options.command = command;
  options.port = static_cast<std::uint16_t>(port >= 0 ? port : (command.empty() ? (operator_suite ? 4001 : 4000) : 0));
  if (!out_dir.empty()) {
    std::error_code error;
    std::filesystem::create_directories(out_dir + "/clients", error);
    if (error) {
      std::cerr << "ocp_conformance: cannot create " << out_dir << ": " << error.message() << "\n";
      return 2;
    }
    options.client_log_dir = out_dir + "/clients";
  }
  signal(SIGINT, on_signal);
  signal(SIGTERM, on_signal);
  signal(SIGPIPE, SIG_IGN);

  std::string client = "external client on 127.0.0.1:" + std::to_string(options.port);
  if (!command.empty()) {
    client.clear();
    for (const auto& word : command) client += (client.empty() ? "" : " ") + word;
  }
  std::cout << "ocp_conformance " << suite_name << ": " << cases.size() << " cases against " << client << "\n";
  if (command.empty()) std::cout << "waiting for the client to connect to 127.0.0.1:" << options.port << " …\n";
  options.on_result = [](const CaseResult& r) {
    print_case_line(std::cout, r);
    std::cout.flush();
  };
  const RunSummary summary = run_cases(cases, options);

  std::optional<BaselineDiff> diff;
  if (baseline) diff = diff_baseline(*baseline, summary.results);
  ReportContext context{suite_name, client, &summary, diff ? &*diff : nullptr};
  print_summary(std::cout, context);
  bool wrote = true;
  if (!out_dir.empty()) {
    wrote = write_file(out_dir + "/index.json", index_json(context)) && write_file(out_dir + "/report.html", html_report(context));
    std::cout << "Reports: " << out_dir << "/index.json, " << out_dir << "/report.html\n";
  }
  if (!junit.empty()) wrote = write_file(junit, junit_xml(context)) && wrote;
  if (!write_baseline.empty()) wrote = write_file(write_baseline, baseline_text(summary.results)) && wrote;
  if (!wrote) {
    std::cerr << "ocp_conformance: could not write a report\n";
    return 2;
  }
  if (!summary.harness_error.empty()) return 2;
  return exit_code(summary.results, baseline ? &*baseline : nullptr);
}
