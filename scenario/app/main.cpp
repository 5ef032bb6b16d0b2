// ocp_scenario: runs scenario files in virtual time and judges their expectations.
//   ocp_scenario run FILE… | DIR [--seed N] [--repeat K] [--junit FILE] [--out DIR] [--list]
//                [--time virtual|real] [--operator-client 'CMD {port}'] [-- CMD ARGS…]
//   ocp_scenario extract-link TRACE [--vehicle NAME] [--rtt-half] > drive.link
// Exit codes: 0 every expectation passed, 1 an expectation failed, 2 bad command line, bad file
// or harness error, 130 interrupted (SIGINT / SIGTERM: the reports so far are written).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "launched_clients.hpp"
#include "scenario/extract_link.hpp"
#include "scenario/limit_options.hpp"
#include "scenario/metrics.hpp"
#include "scenario/parse.hpp"
#include "scenario/reports.hpp"
#include "scenario/runner.hpp"
#include "scenario/verdicts.hpp"
#include "ocp/bounded_file.hpp"
#include "ocp/cli_checks.hpp"
#include "ocp/cli_parse.hpp"
#include "ocp/cli_paths.hpp"
#include "ocp/interrupt.hpp"
#include "sim_app/client_process.hpp"
#include "world/seeds.hpp"

namespace fs = std::filesystem;
using namespace ocp::scenario;

namespace {

constexpr int exit_pass = ocp::cli::exit_ok, exit_fail = ocp::cli::exit_failed, exit_error = ocp::cli::exit_usage_error,
              exit_interrupted = ocp::cli::exit_interrupted;

std::vector<std::string> expand(const std::vector<std::string>& inputs) {
  std::vector<std::string> files;
  for (const std::string& input : inputs) {
    if (fs::is_directory(input)) {
      std::vector<std::string> found;
      for (const auto& entry : fs::directory_iterator(input)) {
        const auto ext = entry.path().extension();
        if (entry.is_regular_file() && (ext == ".yaml" || ext == ".yml")) found.push_back(entry.path().string());
      }
      std::sort(found.begin(), found.end());
      files.insert(files.end(), found.begin(), found.end());
    } else {
      files.push_back(input);
    }
  }
  return files;
}

bool write_file(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  return static_cast<bool>(out);
}

// `ocp_scenario run`'s command line.
struct ToolOptions {
  std::vector<std::string> inputs;
  std::optional<std::uint64_t> seed;
  unsigned repeat = 1;
  std::string junit, out_dir = "scenario-results";
  bool list = false, no_trace = false, trace_payloads = false, realtime = false;
  std::uint16_t tcp_port = 4000;
  double max_file_mb = 0, max_simulated_h = 0;   // 0: the defaults (ocp/bounded_file.hpp, ParseLimits)
  std::uint64_t max_events_per_s = 0;
  std::string time;                     // --time; "" → virtual, or real with --realtime
  bool wait_for_clients = false;        // real time: the clock starts at the clients' connection
  LaunchOptions launch;                 // -- CMD ARGS…, --operator-client, their timeouts
  bool real_time() const { return realtime || time == "real"; }
  bool launching() const { return !launch.command.empty() || !launch.operator_command.empty(); }
};

// --max-file-mb: raises the cap of every scenario, trace and recording file (the defaults are
// in docs/usage.md, "Input files").
void add_max_file_option(CLI::App& command, double& megabytes) {
  command.add_option("--max-file-mb", megabytes, "raise the size cap of input files (scenario 1, traces 64 MB)")
      ->check(ocp::cli::real(1, 65'536));
}

void apply_input_limits(const ToolOptions& options) {
  if (options.max_file_mb > 0) ocp::raise_file_caps(static_cast<std::uint64_t>(options.max_file_mb * 1024 * 1024));
  if (options.max_simulated_h > 0) {
    ParseLimits limits = parse_limits();
    limits.max_run_duration = ocp::Micros{static_cast<std::int64_t>(options.max_simulated_h * 3600e6)};
    set_parse_limits(limits);
  }
  apply_max_events(options.max_events_per_s);
}

// The clock, and the clients the tool launches itself (launched_clients.hpp).
void add_launch_options(CLI::App& run, ToolOptions& options) {
  run.add_option("--time", options.time,
                 "virtual (the default: exact and reproducible; a launched client runs on the world's clock "
                 "through a preloaded shim, docs/virtual-time.md) or real (wall clock, as --realtime)")
      ->check(CLI::IsMember({"virtual", "real"}));
  run.add_option("--operator-client", options.launch.operator_command,
                 "launch this operator client (a shell line with {port}, also $OCP_PORT) on the Player's :4001 API "
                 "(in both times; in real time the clock waits for its connection too)")
      ->check(CLI::Validator(
          [](std::string& text) {
            return text.find_first_not_of(" \t") == std::string::npos ? std::string("empty command") : std::string();
          },
          "CMD"));
  run.add_option("--connect-timeout-s", options.launch.connect_timeout_s,
                 "real time: the launched clients must connect within this (the clock starts then)")
      ->capture_default_str()->check(ocp::cli::real(0.1, 600.0));
  run.add_option("--world-timeout", options.launch.world_timeout_s,
                 "virtual time with launched clients: wall seconds a run may take (a hang never hangs the tool)")
      ->capture_default_str()->check(ocp::cli::real(1.0, 86'400.0));
  run.add_flag("--wait-for-clients", options.wait_for_clients,
               "real time, clients started by hand: the clock starts when every external vehicle's client connected "
               "(at most --connect-timeout-s)");
}

void add_run_command(CLI::App& app, ToolOptions& options) {
  CLI::App* run = app.add_subcommand("run", "run scenario files (or every *.yaml in a folder)");
  run->add_option("files", options.inputs, "scenario files or folders")->required();
  // As in the simulators: a sign, a fraction or a number past 2^64-1 is refused, not wrapped.
  run->add_option("--seed", options.seed, "override every file's seed")->type_name("N")->check(ocp::cli::whole());
  run->add_option("--repeat", options.repeat, "run each file K times with seeds derived from its seed")->check(CLI::Range(1u, 100000u));
  run->add_option("--junit", options.junit, "write JUnit XML (one testsuite per run, one testcase per expectation)")
      ->check(ocp::cli::writable_file());
  run->add_option("--out", options.out_dir, "results folder (trace.jsonl, summary.json, report.html per run)")
      ->check(ocp::cli::writable_folder())->capture_default_str();
  run->add_flag("--list", options.list, "list files and expectations without running");
  run->add_flag("--no-trace", options.no_trace, "do not write trace.jsonl (faster long runs)");
  run->add_flag("--trace-payloads", options.trace_payloads, "include every frame's payload in trace.jsonl");
  run->add_flag("--realtime", options.realtime,
                "run in real time (not reproducible); vehicles with in_process_client: false wait for "
                "external vehicle clients over TCP");
  run->add_option("--tcp-port", options.tcp_port, "--realtime: port of the first external vehicle (the next +1, …; 0: any)")
      ->capture_default_str();
  add_launch_options(*run, options);
  add_max_file_option(*run, options.max_file_mb);
  run->add_option("--max-simulated-h", options.max_simulated_h, "raise the ceiling of one run's duration (default 24 h)")
      ->check(ocp::cli::real(1, 1'000'000));
  add_max_events_option(*run, options.max_events_per_s);
}

// A run's trace → a link recording on stdout (docs/link-recording.md).
CLI::App* add_extract_link_command(CLI::App& app, ExtractLinkOptions& options, ToolOptions& limits) {
  CLI::App* extract = app.add_subcommand("extract-link", "write a link recording (for link: {replay: FILE}) of one "
                                                         "vehicle from a run's trace.jsonl, to stdout");
  extract->add_option("trace", options.trace_path, "a run's trace.jsonl")->required();
  extract->add_option("--vehicle", options.vehicle, "the vehicle whose link to record (needed when the trace has several)");
  extract->add_flag("--rtt-half", options.rtt_half,
                    "the two ends' clocks differ (a two-host run): every delay is the Streamer's RTT/2");
  add_max_file_option(*extract, limits.max_file_mb);
  return extract;
}

// Every file is parsed before any runs, so that one bad file is reported without running the
// others first (and all bad files at once). Empty: nothing to run (the errors are printed).
std::vector<Scenario> load_every_scenario(const std::vector<std::string>& files) {
  std::vector<Scenario> scenarios;
  bool bad = false;
  for (const std::string& file : files) {
    try {
      scenarios.push_back(load_scenario(file));
      for (const std::string& warning : scenarios.back().warnings) std::cerr << "warning: " << warning << "\n";
    } catch (const ScenarioError& error) {
      std::cerr << "error: " << error.what() << "\n";
      bad = true;
    }
  }
  if (bad) return {};
  if (scenarios.empty()) std::cerr << "error: no scenario files found\n";
  return scenarios;
}

void print_expectations(const std::vector<Scenario>& scenarios) {
  for (const Scenario& scenario : scenarios) {
    std::cout << scenario.path << "  (seed " << scenario.seed << ", " << scenario.expectations.size() << " expectations)\n";
    for (const Expectation& expectation : scenario.expectations) {
      std::cout << "  - " << expectation.title << "  [line " << expectation.mark.line << "]\n";
    }
  }
}

// OUT/<scenario>[/seed-N]: a folder per seed when a file runs more than once.
fs::path run_folder(const ToolOptions& tool, const Scenario& scenario, std::uint64_t run_seed) {
  fs::path dir = fs::path(tool.out_dir) / scenario.name;
  if (tool.repeat > 1) dir /= "seed-" + std::to_string(run_seed);
  return dir;
}

// One run in virtual time, or in real time waiting for the external vehicle clients, or with
// the clients launched by the tool (then with a verdict per client process). The trace goes to
// its file as the run goes, so a long run's memory stays flat.
LaunchedRun run_once(const Scenario& scenario, const ToolOptions& tool, std::uint64_t run_seed) {
  RunOptions options;
  options.seed = run_seed;
  options.trace = !tool.no_trace;
  if (options.trace) {
    const fs::path dir = run_folder(tool, scenario, run_seed);
    std::error_code ec;
    fs::create_directories(dir, ec);
    options.trace_file = (dir / "trace.jsonl").string();
  }
  options.trace_payloads = tool.trace_payloads;
  options.interrupted = ocp::cli::interrupt_requested;
  if (tool.launching()) {
    LaunchOptions launch = tool.launch;
    launch.virtual_time = !tool.real_time();
    launch.log_dir = run_folder(tool, scenario, run_seed).string();
    std::error_code ec;
    fs::create_directories(launch.log_dir, ec);
    LaunchedRun ran = run_with_launched_clients(scenario, options, launch);
    if (!launch.virtual_time) ocp::cli::install_interrupt_handlers(ocp::sim_app::kill_all_clients);
    return ran;
  }
  if (!tool.real_time()) return {run_scenario(scenario, options), {}};
  RealTimeOptions real_time;
  real_time.tcp_port = tool.tcp_port;
  real_time.start_at_connection = tool.wait_for_clients;
  real_time.connect_timeout = std::chrono::milliseconds(static_cast<std::int64_t>(tool.launch.connect_timeout_s * 1000));
  real_time.on_listening = [](const std::string& vehicle, const std::string& address) {
    std::printf("%s: waiting for a vehicle client on %s\n", vehicle.c_str(), address.c_str());
    std::fflush(stdout);
  };
  RunResult result = run_scenario_realtime(scenario, options, real_time);
  ocp::cli::install_interrupt_handlers();   // the real-time runner's signal handling put the default action back
  return {std::move(result), {}};
}

// A word of a command line as the shell reads it back: quoted when it holds more than
// [A-Za-z0-9_./:{}=@%+-].
std::string shell_word(const std::string& word) {
  if (!word.empty() && word.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_./:{}=@%+-") ==
                           std::string::npos) {
    return word;
  }
  std::string quoted = "'";
  for (const char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// The command that repeats a run: its seed, its clock, and the clients the tool launched.
std::string reproduce_command(const Scenario& scenario, const ToolOptions& tool, std::uint64_t run_seed) {
  std::string command = "ocp_scenario run " + shell_word(scenario.path) + " --seed " + std::to_string(run_seed);
  if (!tool.launching()) return command + (tool.real_time() ? " --realtime (real time: not reproducible)" : "");
  if (tool.real_time()) command += " --time real";
  if (!tool.launch.operator_command.empty()) command += " --operator-client " + shell_word(tool.launch.operator_command);
  if (!tool.launch.command.empty()) {
    command += " --";
    for (const std::string& word : tool.launch.command) command += " " + shell_word(word);
  }
  return command + (tool.real_time() ? " (real time: not reproducible)" : "");
}

// What the closing line adds up over every run.
struct Tally {
  std::size_t passed = 0, failed = 0, not_judged = 0, runs_failed = 0;
  double simulated_s = 0;
};

// A run's headline (speed against the wall clock and the CPU), its verdicts, and how to
// reproduce it when it failed.
void print_run(const RunReport& report, std::uint64_t run_seed, Tally& tally) {
  const RunResult& result = *report.run;
  const bool ok = all_passed(report.verdicts);
  const double sim_s = static_cast<double>(result.ran.count()) / 1e6;
  tally.simulated_s += sim_s;
  const char* mark = result.interrupted ? "○" : ok ? "✓" : "✗";
  std::printf("\n%s %s  seed %llu  %.1fs simulated in %.3fs wall (%.0f:1), %.3fs CPU (%.0f:1)%s\n", mark,
              report.scenario->path.c_str(), static_cast<unsigned long long>(run_seed), sim_s, result.wall_seconds,
              result.wall_seconds > 0 ? sim_s / result.wall_seconds : 0.0, result.cpu_seconds,
              result.cpu_seconds > 0 ? sim_s / result.cpu_seconds : 0.0,
              result.interrupted ? ("  interrupted at " + format_seconds(result.ran)).c_str() : "");
  std::cout << console_verdicts(report);
  if (!ok) std::cout << "  reproduce: " << report.reproduce << "\n";
  bool failed = false;
  for (const Verdict& verdict : report.verdicts) {
    failed = failed || (!verdict.passed && !verdict.interrupted);
    if (verdict.interrupted) ++tally.not_judged;
    else (verdict.passed ? tally.passed : tally.failed)++;
  }
  tally.runs_failed += failed ? 1 : 0;
}

// summary.json and report.html beside the run's trace.jsonl (written while it ran).
bool write_run_results(const ToolOptions& tool, const RunReport& report, std::uint64_t run_seed) {
  const fs::path dir = run_folder(tool, *report.scenario, run_seed);
  std::error_code ec;
  fs::create_directories(dir, ec);
  const std::string summary = summary_json(report);
  const bool written = write_file(dir / "summary.json", summary) &&
                       write_file(dir / "report.html", report_html(report, summary));
  if (ec || !written) {
    std::cerr << "error: cannot write results to " << dir << "\n";
    return false;
  }
  return true;
}

// Each file `repeat` times: the first run with the file's seed (or --seed), the others with
// seeds derived from it, so that every run can be reproduced alone. Ctrl-C stops the run in
// progress: its reports (marked interrupted) and those of the finished runs are written.
int run_every_scenario(const std::vector<Scenario>& scenarios, const ToolOptions& tool) {
  const auto wall_start = std::chrono::steady_clock::now();
  // A second Ctrl-C ends the tool at once: launched clients are killed first.
  ocp::cli::install_interrupt_handlers(tool.launching() ? ocp::sim_app::kill_all_clients : nullptr);
  std::vector<RunResult> runs;
  runs.reserve(scenarios.size() * tool.repeat);   // RunReport points into it
  std::vector<RunReport> reports;
  Tally tally;
  bool interrupted = false;
  for (const Scenario& scenario : scenarios) {
    const std::uint64_t base_seed = tool.seed.value_or(scenario.seed);
    for (unsigned k = 0; k < tool.repeat && !interrupted; ++k) {
      const std::uint64_t run_seed = k == 0 ? base_seed : ocp::derive_seed(base_seed, "repeat:" + std::to_string(k));
      std::vector<Verdict> client_verdicts;
      try {
        LaunchedRun ran = run_once(scenario, tool, run_seed);
        runs.push_back(std::move(ran.result));
        client_verdicts = std::move(ran.client_verdicts);
      } catch (const HarnessError& error) {
        std::cerr << "error: " << scenario.path << ": " << error.what() << "\n";
        return exit_error;
      }
      const RunResult& result = runs.back();
      RunReport report{&scenario, &result, evaluate(scenario, result), reproduce_command(scenario, tool, run_seed)};
      report.verdicts.insert(report.verdicts.end(), client_verdicts.begin(), client_verdicts.end());
      print_run(report, run_seed, tally);
      if (!write_run_results(tool, report, run_seed)) return exit_error;
      // What is kept for the closing summary and JUnit is the verdicts and the run's headline:
      // the observations go, so --repeat 10000 holds no more than one run's series at a time.
      runs.back().observations = Observations{};
      runs.back().trace_jsonl.clear();
      reports.push_back(std::move(report));
      interrupted = result.interrupted || ocp::cli::interrupt_requested();
    }
    if (interrupted) break;
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  if (tool.repeat > 1) std::cout << repeat_summary(reports);
  std::printf("\nchecks: %zu passed, %zu failed", tally.passed, tally.failed);
  if (tally.not_judged > 0) std::printf(", %zu not judged (interrupted)", tally.not_judged);
  std::printf("; runs: %zu, %zu failed; %.1fs simulated in %.2fs wall; results in %s\n", reports.size(), tally.runs_failed,
              tally.simulated_s, wall_s, tool.out_dir.c_str());
  if (!tool.junit.empty() && !write_file(tool.junit, junit_xml(reports, interrupted))) {
    std::cerr << "error: cannot write " << tool.junit << "\n";
    return exit_error;
  }
  if (interrupted) {
    std::printf("interrupted: %zu run(s) written to %s, marked \"interrupted\": true where cut short\n", reports.size(),
                tool.out_dir.c_str());
    std::fflush(stdout);
    return exit_interrupted;
  }
  return tally.failed == 0 ? exit_pass : exit_fail;
}

// The clock options that contradict each other, in words ("" when they do not).
std::string clock_problem(const ToolOptions& options, bool had_separator) {
  if (options.realtime && options.time == "virtual") return "--realtime and --time virtual contradict each other";
  if (had_separator && options.launch.command.empty()) return "-- needs the client's command after it";
  if (options.wait_for_clients && !options.real_time()) return "--wait-for-clients is for real time (--time real)";
  if (options.wait_for_clients && options.launching()) return "--wait-for-clients is for clients started by hand";
  return "";
}

}  // namespace

int run_tool(int argc, char** argv);

int main(int argc, char** argv) {
  try {
    return run_tool(argc, argv);
  } catch (const std::exception& error) {
    // Anything unexpected (a results folder that cannot be made, …) is a harness error.
    std::cerr << "error: " << error.what() << "\n";
    return 2;
  }
}

int run_tool(int argc, char** argv) {
  CLI::App app{"ocp_scenario: scenario files with verdicts, run in virtual time (docs/scenarios.md)", "ocp_scenario"};
  app.require_subcommand(1);
  ToolOptions options;
  add_run_command(app, options);
  ExtractLinkOptions extract;
  const CLI::App* extract_command = add_extract_link_command(app, extract, options);
  // `run FILE -- CMD ARGS…`: what follows "--" is the client's command line, not the tool's.
  int tool_argc = argc;
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) != "--") continue;
    options.launch.command.assign(argv + i + 1, argv + argc);
    tool_argc = i;
    break;
  }
  // --help is exit 0; a bad command line is a harness error like a bad file: 2.
  if (auto exit_code = ocp::cli::parse_or_exit_code(app, tool_argc, argv)) return *exit_code;
  if (const std::string problem = clock_problem(options, tool_argc < argc); !problem.empty()) {
    std::cerr << "ocp_scenario run: " << problem << "\nRun with --help for more information.\n";
    return exit_error;
  }
  apply_input_limits(options);
  if (extract_command->parsed()) return extract_link_command(extract, std::cout, std::cerr);
  const std::vector<Scenario> scenarios = load_every_scenario(expand(options.inputs));
  if (scenarios.empty()) return exit_error;
  if (options.list) {
    print_expectations(scenarios);
    return exit_pass;
  }
  if (options.launching()) {
    LaunchOptions launch = options.launch;
    launch.virtual_time = !options.real_time();
    for (const Scenario& scenario : scenarios) {
      if (const std::string problem = launch_problem(scenario, launch); !problem.empty()) {
        std::cerr << "error: " << scenario.path << ": " << problem << "\n";
        return exit_error;
      }
    }
  }
  return run_every_scenario(scenarios, options);
}
