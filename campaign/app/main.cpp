// ocp_campaign: seeded random worlds against an independent oracle (docs/campaigns.md).
//   ocp_campaign run   --seed S --worlds N [--profile P] [-j J] [--shard I/N] [--out DIR] [--world I]
//                      [--client 'CMD {port}' [--time virtual|real] [--max-world-seconds S]]
//   ocp_campaign check FILE.yaml          (one scenario file under the oracle: the repro command)
//   ocp_campaign merge DIR… --out DIR     (shard results → one result, as one run would write it)
//   ocp_campaign slurm …                  (an sbatch job array of shards, then merge)
// Exit codes: 0 no failure, 1 a world failed, 2 bad usage or input, 130 interrupted (Ctrl-C).
#include <CLI/CLI.hpp>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <sstream>
#include <unistd.h>

#include "campaign/campaign.hpp"
#include "campaign/efficiency.hpp"
#include "campaign/failure_files.hpp"
#include "campaign/generator.hpp"
#include "campaign/results.hpp"
#include "campaign/script_names.hpp"
#include "campaign/shell_words.hpp"
#include "campaign/slurm.hpp"
#include "campaign/world_check.hpp"
#include "ocp/bounded_file.hpp"
#include "ocp/cli_checks.hpp"
#include "ocp/cli_parse.hpp"
#include "ocp/cli_paths.hpp"
#include "sim_app/client_process.hpp"
#include "ocp/exit_codes.hpp"
#include "ocp/interrupt.hpp"
#include "scenario/limit_options.hpp"
#include "scenario/parse.hpp"

namespace fs = std::filesystem;
using namespace ocp::campaign;

namespace {

constexpr int exit_pass = ocp::cli::exit_ok, exit_fail = ocp::cli::exit_failed, exit_usage = ocp::cli::exit_usage_error,
              exit_interrupted = ocp::cli::exit_interrupted;


void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

std::string read_text(const fs::path& path) {
  auto text = ocp::read_bounded_file(path.string(), ocp::file_kinds::summary);
  if (!text) throw std::runtime_error(text.error().detail);
  return std::move(*text);
}

// A profile argument is a shipped profile's name ("default", "calm") or a file.
Profile resolve_profile(const std::string& argument) {
  if (argument.find('/') == std::string::npos && argument.find('.') == std::string::npos) {
    return load_profile(shipped_profile_path(argument));
  }
  return load_profile(argument);
}

// "I/N" with 0 ≤ I < N ≤ 100000.
std::optional<Shard> parse_shard(const std::string& text, std::string& error) {
  const auto slash = text.find('/');
  try {
    if (slash == std::string::npos) throw std::invalid_argument("no slash");
    std::size_t used = 0;
    const unsigned long index = std::stoul(text.substr(0, slash), &used);
    if (used != slash) throw std::invalid_argument("index");
    const std::string count_text = text.substr(slash + 1);
    const unsigned long count = std::stoul(count_text, &used);
    if (used != count_text.size()) throw std::invalid_argument("count");
    if (count < 1 || count > 100'000 || index >= count) throw std::out_of_range("range");
    return Shard{static_cast<std::uint32_t>(index), static_cast<std::uint32_t>(count)};
  } catch (const std::exception&) {
    error = "--shard: expected I/N with 0 <= I < N <= 100000, got '" + text + "'";
    return std::nullopt;
  }
}

struct RunCommand {
  std::uint64_t seed = 1;
  std::uint64_t worlds = 100;
  std::string profile = "default";
  int jobs = 1;
  std::string shard;
  std::string out = "campaign-results";
  std::optional<std::uint64_t> world;
  bool no_shrink = false;
  int shrink_runs = 300;
  int shrink_max = 10;
  bool quiet = false;
  std::optional<std::string> client;   // --client: worlds against this vehicle client (--time)
  std::optional<double> max_world_seconds;
  // --time: the client's clock. Virtual by default (docs/virtual-time.md): the reference client and the
  // Python example pass there, with the whole oracle; real for a client that cannot be virtualised.
  std::string time = "virtual";
  double world_timeout_seconds = 120;    // --world-timeout: wall time per virtual-time world
  std::string wait_trace;                // --wait-trace FILE: every client thread's waits
};

// --client's program, checked before any world starts: a command that cannot be found is a
// usage error (exit 2), not a campaign of failed worlds. Only the first word is checked (a
// shell line may set variables first: then the shell says it when the world starts).
std::optional<std::string> client_problem(const std::string& command) {
  const std::string program = first_shell_word(command);
  if (program.empty()) return "--client: empty command";
  if (program.find('=') != std::string::npos) return std::nullopt;
  if (program.find('/') != std::string::npos) {
    if (access(program.c_str(), X_OK) != 0) return "--client: cannot run '" + program + "': " + std::strerror(errno);
    return std::nullopt;
  }
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path != nullptr ? path : "/usr/bin:/bin");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    if (access(((dir.empty() ? "." : dir) + "/" + program).c_str(), X_OK) == 0) return std::nullopt;
  }
  return "--client: cannot run '" + program + "': not found in PATH";
}

// --client and --max-world-seconds as a ClientRun (client logs under <out>/client-logs).
std::optional<ClientRun> client_run_of(const RunCommand& command) {
  if (!command.client) return std::nullopt;
  ClientRun run;
  run.command = *command.client;
  if (command.max_world_seconds) run.max_world = ocp::Micros{static_cast<std::int64_t>(*command.max_world_seconds * 1e6)};
  run.log_dir = (fs::path(command.out) / "client-logs").string();
  if (command.time == "virtual") {
    run.time = ClientTime::virtual_time;
    run.bounds = virtual_time_client_bounds();
    run.controller.shim_path = ocp::vtime::find_shim();
    run.controller.watchdog = std::chrono::milliseconds(static_cast<std::int64_t>(command.world_timeout_seconds * 1000));
    run.controller.wait_trace_path = command.wait_trace;
  }
  return run;
}

// The shard: --shard, else SLURM_ARRAY_TASK_ID / SLURM_ARRAY_TASK_COUNT, else the whole campaign.
std::optional<Shard> choose_shard(const RunCommand& command, std::string& error) {
  if (!command.shard.empty()) return parse_shard(command.shard, error);
  const char* id = std::getenv("SLURM_ARRAY_TASK_ID");
  const char* count = std::getenv("SLURM_ARRAY_TASK_COUNT");
  if (id != nullptr && count != nullptr) {
    const auto shard = parse_shard(std::string(id) + "/" + count, error);
    if (!shard) error = "SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT: expected 0 <= id < count, got " + std::string(id) + "/" + count;
    return shard;
  }
  return Shard{};
}

class ProgressLine {
 public:
  explicit ProgressLine(bool quiet) : quiet_(quiet), tty_(isatty(STDERR_FILENO) != 0) {}
  void update(const Progress& p) {
    if (quiet_) return;
    const auto now = std::chrono::steady_clock::now();
    const auto every = tty_ ? std::chrono::milliseconds(250) : std::chrono::milliseconds(5000);
    if (p.done != p.total && now - last_ < every) return;
    last_ = now;
    std::fprintf(stderr, "%s%llu/%llu worlds  %.1f worlds/s  %llu failures%s", tty_ ? "\r" : "",
                 static_cast<unsigned long long>(p.done), static_cast<unsigned long long>(p.total),
                 p.wall_seconds > 0 ? static_cast<double>(p.done) / p.wall_seconds : 0.0,
                 static_cast<unsigned long long>(p.failures), tty_ ? "   " : "\n");
    if (tty_ && p.done == p.total) std::fputc('\n', stderr);
  }
  void end() {
    if (!quiet_ && tty_) std::fputc('\n', stderr);
  }

 private:
  bool quiet_, tty_;
  std::chrono::steady_clock::time_point last_{};
};

// summary.json, junit.xml and index.html of a summary, in `out`.
void write_outputs(const Summary& summary, const fs::path& out) {
  fs::create_directories(out);
  write_text(out / "summary.json", summary_json(summary));
  write_text(out / "junit.xml", junit_xml(summary));
  write_text(out / "index.html", html_index(summary));
}

// The campaign options of a run command; false (after saying why) on a usage error.
bool campaign_options_of(const RunCommand& command, CampaignOptions& options) {
  try {
    options.profile = resolve_profile(command.profile);
  } catch (const ProfileError& error) {
    std::cerr << "ocp_campaign run: " << error.what() << "\n";
    return false;
  }
  std::string error;
  const auto shard = choose_shard(command, error);
  if (!shard) {
    std::cerr << "ocp_campaign run: " << error << "\n";
    return false;
  }
  if (command.world && *command.world >= command.worlds) {
    std::cerr << "ocp_campaign run: --world " << *command.world << " is not below --worlds " << command.worlds << "\n";
    return false;
  }
  if (command.client) {
    if (const auto problem = client_problem(*command.client)) {
      std::cerr << "ocp_campaign run: " << *problem << "\n";
      return false;
    }
    if (command.time == "virtual" && ocp::vtime::find_shim().empty()) {
      std::cerr << "ocp_campaign run: --time virtual needs the shim libocp_vtime_shim.so (beside the program in "
                   "../lib, or in $OCP_VTIME_SHIM); use --time real\n";
      return false;
    }
    std::error_code made;
    fs::create_directories(fs::path(command.out) / "client-logs", made);
  }
  options.seed = command.seed;
  options.worlds = command.worlds;
  options.jobs = command.jobs;
  options.shard = *shard;
  options.stop = ocp::cli::interrupt_requested;
  options.client = client_run_of(command);
  return true;
}

// --world I: one world, for a repro: same generator, same checks, its violations printed.
int run_one_world(const CampaignOptions& options, std::uint64_t index) {
  const WorldOutcome outcome = check_campaign_world(options, index);
  if (!outcome.error.empty()) {
    std::cerr << "ocp_campaign run: world " << index << ": " << outcome.error << "\n";
    return exit_usage;
  }
  for (const Violation& v : outcome.violations) {
    std::cout << check_name(v.check) << " at " << v.at.count() << " us " << v.vehicle << ": " << v.detail << "\n";
  }
  return outcome.failed() ? exit_fail : exit_pass;
}

// The results folder: each failure's folder (shrunk, up to --shrink-max), then the summary,
// JUnit and index, which name the files each folder got.
void write_campaign_results(const RunCommand& command, const CampaignOptions& options, Summary& summary) {
  FailureFilesOptions files{command.out, command.seed, command.worlds, command.profile, !command.no_shrink,
                            command.shrink_runs, std::nullopt};
  if (options.client) {
    files.client = FailureFilesOptions::Client{*command.client, command.max_world_seconds, options.client->max_world, std::nullopt};
    if (options.client->time == ClientTime::virtual_time) files.client->run = options.client;
  }
  int shrunk = 0;
  for (WorldRecord& record : summary.records) {
    if (!record.failed() || ocp::cli::interrupt_requested()) continue;
    files.shrink = !command.no_shrink && shrunk < command.shrink_max;
    FailureFiles made = write_failure_files(options.profile, record.index, files);
    record.files = std::move(made.files);
    record.replay = std::move(made.replay);
    ++shrunk;
  }
  write_outputs(summary, fs::path(command.out));
}

// The closing efficiency lines, and efficiency.json beside the results (efficiency.hpp).
void report_efficiency(const CampaignRun& run, const std::string& out) {
  const Efficiency efficiency = efficiency_of(run);
  std::cout << efficiency_text(efficiency);
  std::ofstream(fs::path(out) / "efficiency.json") << efficiency_json(efficiency);
}

int run_command(const RunCommand& command) {
  CampaignOptions options;
  if (!campaign_options_of(command, options)) return exit_usage;
  ocp::cli::install_interrupt_handlers(ocp::sim_app::kill_all_clients);
  if (command.world) return run_one_world(options, *command.world);
  ProgressLine progress(command.quiet);
  const CampaignRun run = run_campaign(options, [&](const Progress& p) { progress.update(p); });
  progress.end();
  if (!run.harness_error.empty()) {
    std::cerr << "ocp_campaign run: " << run.harness_error << "\n";
    return exit_usage;
  }
  Summary summary = summarise(options, run);
  try {
    write_campaign_results(command, options, summary);
  } catch (const std::exception& failure) {
    std::cerr << "ocp_campaign run: " << failure.what() << "\n";
    return exit_usage;
  }
  std::cout << summary_table(summary);
  report_efficiency(run, command.out);
  std::cout << "results: " << (fs::path(command.out) / "index.html").string() << "\n";
  if (run.interrupted || ocp::cli::interrupt_requested()) {
    std::cout << "interrupted\n";
    return exit_interrupted;
  }
  for (const WorldRecord& record : summary.records) {
    if (record.failed()) return exit_fail;
  }
  return exit_pass;
}

int check_command(const std::string& file) {
  ocp::scenario::Scenario scenario;
  try {
    scenario = ocp::scenario::load_scenario(file);
  } catch (const ocp::scenario::ScenarioError& error) {
    std::cerr << error.what() << "\n";
    return exit_usage;
  }
  const WorldOutcome outcome = check_world(scenario, {true});
  if (!outcome.error.empty()) {
    std::cerr << file << ": " << outcome.error << "\n";
    return exit_usage;
  }
  for (const Violation& v : outcome.violations) {
    std::cout << check_name(v.check) << " at " << v.at.count() << " us" << (v.vehicle.empty() ? "" : " on " + v.vehicle)
              << ": " << v.detail << "\n";
  }
  std::cout << file << ": " << (outcome.failed() ? "FAIL" : "pass") << " (" << outcome.violation_count << " violations)\n";
  return outcome.failed() ? exit_fail : exit_pass;
}

int merge_command(const std::vector<std::string>& inputs, const std::string& out_dir) {
  std::vector<Summary> shards;
  try {
    for (const std::string& input : inputs) {
      const fs::path path = fs::is_directory(input) ? fs::path(input) / "summary.json" : fs::path(input);
      shards.push_back(read_summary_json(read_text(path), path.string()));
    }
    const Summary merged = merge_summaries(shards);
    const fs::path out(out_dir);
    write_outputs(merged, out);
    // Each failure's folder, from the shard that ran it.
    for (const std::string& input : inputs) {
      const fs::path dir = fs::is_directory(input) ? fs::path(input) : fs::path(input).parent_path();
      if (fs::exists(dir / "failures") && fs::weakly_canonical(dir) != fs::weakly_canonical(out)) {
        fs::create_directories(out / "failures");
        fs::copy(dir / "failures", out / "failures", fs::copy_options::recursive | fs::copy_options::overwrite_existing);
      }
    }
    std::cout << summary_table(merged);
    for (const WorldRecord& record : merged.records) {
      if (record.failed()) return exit_fail;
    }
    return merged.interrupted ? exit_interrupted : exit_pass;
  } catch (const MergeError& error) {
    std::cerr << "ocp_campaign merge: " << error.what() << "\n";
    return exit_usage;
  } catch (const std::exception& error) {
    std::cerr << "ocp_campaign merge: " << error.what() << "\n";
    return exit_usage;
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ocp_campaign: seeded random worlds against an independent oracle (docs/campaigns.md)", "ocp_campaign"};
  app.require_subcommand(1);
  RunCommand run;
  CLI::App* run_app = app.add_subcommand("run", "run a campaign (or one shard of it)");
  run_app->add_option("--seed", run.seed, "campaign seed")->check(ocp::cli::whole())->capture_default_str();
  run_app->add_option("--worlds", run.worlds, "worlds in the campaign")->check(ocp::cli::whole(1, 10'000'000))->capture_default_str();
  run_app->add_option("--profile", run.profile, "generator profile: default, calm, or a YAML file")
      ->check(script_name())->capture_default_str();
  run_app->add_option("-j,--jobs", run.jobs, "worker threads")->check(CLI::Range(1, 256))->capture_default_str();
  run_app->add_option("--shard", run.shard, "run shard I of N (worlds i with i % N == I); default from SLURM_ARRAY_TASK_ID/COUNT");
  run_app->add_option("--out", run.out, "results folder")->check(script_name())->check(ocp::cli::writable_folder())->capture_default_str();
  run_app->add_option("--world", run.world, "run only this world (a repro) and print its violations");
  run_app->add_flag("--no-shrink", run.no_shrink, "do not shrink failing worlds");
  run_app->add_option("--shrink-runs", run.shrink_runs, "world runs allowed per shrink")->check(CLI::Range(1, 100'000))->capture_default_str();
  run_app->add_option("--shrink-max", run.shrink_max, "failing worlds to shrink (the rest get world.yaml only)")
      ->check(CLI::Range(0, 100'000))->capture_default_str();
  run_app->add_flag("-q,--quiet", run.quiet, "no progress line");
  run_app->add_option("--client", run.client,
                      "run every world against this vehicle client, a shell command line with {port} (also in env "
                      "OCP_PORT); one process per vehicle, output in OUT/client-logs");
  run_app->add_option("--time", run.time,
                      "with --client: virtual (the default: the client lives on the simulator's clock through a preloaded "
                      "shim; the whole oracle, shrinking; docs/virtual-time.md) or real (wall-clock worlds, timing "
                      "checks off; for a static binary or Go)")
      ->check(CLI::IsMember({"virtual", "real"}))->capture_default_str();
  run_app->add_option("--world-timeout", run.world_timeout_seconds, "with --time virtual: wall seconds a world may take")
      ->check(ocp::cli::real(1.0, 86'400.0))->capture_default_str();
  run_app->add_option("--wait-trace", run.wait_trace, "with --time virtual: write every client thread's waits to this file (-j 1)")
      ->check(script_name());
  run_app->add_option("--max-world-seconds", run.max_world_seconds, "with --client: cut every world to this long")
      ->check(ocp::cli::real(1.0, 3600.0));

  std::string check_file;
  CLI::App* check_app = app.add_subcommand("check", "run one scenario file under the oracle (exit 1 on a violation)");
  check_app->add_option("file", check_file, "scenario YAML (e.g. a shrunk.yaml)")->required();

  std::vector<std::string> merge_inputs;
  std::string merge_out = "campaign-results";
  CLI::App* merge_app = app.add_subcommand("merge", "join shard results into one summary, JUnit file and HTML index");
  merge_app->add_option("shards", merge_inputs, "shard result folders (or their summary.json)")->required();
  merge_app->add_option("--out", merge_out, "merged results folder")->check(ocp::cli::writable_folder())->capture_default_str();

  // Every profile, scenario and summary file is read under a size cap (ocp/bounded_file.hpp).
  double max_file_mb = 0;
  for (CLI::App* command : {run_app, check_app, merge_app}) {
    command->add_option("--max-file-mb", max_file_mb, "raise the size cap of input files (profile, scenario: 1 MB)")
        ->check(ocp::cli::real(1, 65'536));
  }
  std::uint64_t max_events_per_s = 0;
  for (CLI::App* command : {run_app, check_app}) ocp::scenario::add_max_events_option(*command, max_events_per_s);

  SlurmOptions slurm;
  CLI::App* slurm_app = app.add_subcommand("slurm", "run the campaign as an sbatch job array, wait, and merge");
  add_slurm_options(*slurm_app, slurm);

  if (auto exit_code = ocp::cli::parse_or_exit_code(app, argc, argv)) return *exit_code;
  if (max_file_mb > 0) ocp::raise_file_caps(static_cast<std::uint64_t>(max_file_mb * 1024 * 1024));
  ocp::scenario::apply_max_events(max_events_per_s);
  if (run_app->parsed()) return run_command(run);
  if (check_app->parsed()) return check_command(check_file);
  if (merge_app->parsed()) return merge_command(merge_inputs, merge_out);
  if (slurm_app->parsed()) return run_slurm(slurm);
  return exit_usage;
}
