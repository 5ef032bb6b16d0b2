// `ocp_campaign slurm` (slurm.hpp).
#include "campaign/slurm.hpp"
#include "campaign/script_names.hpp"
#include "campaign/shell_words.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <fstream>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <thread>

#include "campaign/profile.hpp"
#include "ocp/cli_checks.hpp"
#include "ocp/cli_paths.hpp"
#include "ocp/interrupt.hpp"
#include "scenario/limit_options.hpp"

#include <fmt/format.h>

namespace ocp::campaign {

namespace {

constexpr int exit_usage = 2;

// Runs a shell command; its stdout, and whether it exited 0.
std::pair<std::string, bool> capture(const std::string& command) {
  std::string out;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return {"", false};
  std::array<char, 4096> buffer{};
  while (const std::size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe)) out.append(buffer.data(), n);
  const int status = pclose(pipe);
  return {out, status == 0};
}

bool on_path(const std::string& tool) { return capture("command -v " + tool + " >/dev/null 2>&1").second; }

std::string self_executable() {
  std::error_code error;
  const auto path = std::filesystem::read_symlink("/proc/self/exe", error);
  return error ? std::string("ocp_campaign") : path.string();
}

}  // namespace

void add_slurm_options(CLI::App& app, SlurmOptions& options) {
  app.add_option("--seed", options.seed, "campaign seed")->check(cli::whole())->capture_default_str();
  app.add_option("--worlds", options.worlds, "worlds in the campaign")->check(cli::whole(1, 10'000'000))->capture_default_str();
  app.add_option("--profile", options.profile, "generator profile: default, calm, or a YAML file")
      ->check(script_name())->capture_default_str();
  app.add_option("--tasks", options.tasks, "array tasks (shards)")->check(CLI::Range(1, 10'000))->capture_default_str();
  app.add_option("-j,--jobs", options.jobs, "worker threads per task (--cpus-per-task)")->check(CLI::Range(1, 256))->capture_default_str();
  app.add_option("--out", options.out, "results folder (shards in shard-<i>/, merged at the top)")
      ->check(script_name())->check(cli::writable_folder())->capture_default_str();
  app.add_option("--partition", options.partition, "Slurm partition (default: the cluster's)")->check(script_name());
  app.add_option("--poll", options.poll_seconds, "seconds between squeue polls")->check(cli::real(0.05, 600))->capture_default_str();
  app.add_option("--timeout", options.timeout_seconds, "give up waiting after this many seconds")
      ->check(cli::real(1, 7 * 86400))->capture_default_str();
  app.add_flag("--print-only", options.print_only, "print the sbatch script and exit");
  // What `run` takes about the client, passed on to every task as given.
  app.add_option("--client", options.client, "every task runs its worlds against this vehicle client (as run --client)")
      ->check(script_name());
  app.add_option("--time", options.time, "with --client: virtual (the default) or real, as run --time")
      ->check(CLI::IsMember({"virtual", "real"}));
  app.add_option("--max-world-seconds", options.max_world_seconds, "with --client: as run --max-world-seconds")
      ->check(cli::real(1.0, 3600.0));
  app.add_option("--world-timeout", options.world_timeout_seconds, "with --time virtual: as run --world-timeout")
      ->check(cli::real(1.0, 86'400.0));
  scenario::add_max_events_option(app, options.max_events_per_s);
}

namespace {

// A profile that is a file (it has a '/' or a '.') by absolute path: the tasks may start elsewhere.
std::string slurm_profile_argument(const std::string& profile) {
  if (profile.find('/') == std::string::npos && profile.find('.') == std::string::npos) return profile;
  return std::filesystem::absolute(profile).lexically_normal().string();
}

// The options of `run` that slurm passes on as given (" --client '…' --time virtual …"), or "".
std::string passed_on_options(const SlurmOptions& o) {
  std::string line;
  if (!o.client.empty()) line += " --client " + shell_quoted(o.client);
  if (!o.time.empty()) line += " --time " + o.time;
  if (o.max_world_seconds > 0) line += " --max-world-seconds " + fmt::format("{}", o.max_world_seconds);
  if (o.world_timeout_seconds > 0) line += " --world-timeout " + fmt::format("{}", o.world_timeout_seconds);
  if (o.max_events_per_s > 0) line += " --max-events-per-s " + std::to_string(o.max_events_per_s);
  return line;
}

}  // namespace

// Every name in it is quoted (and a name with a control character refused before: a newline would
// end its #SBATCH or comment line and start a command).
std::string sbatch_script(const SlurmOptions& o, const std::string& executable) {
  for (const std::string* name : {&o.out, &o.partition, &o.profile, &executable, &o.client}) {
    if (auto problem = script_name_problem(*name)) throw std::invalid_argument("'" + *name + "': " + *problem);
  }
  const std::string out = std::filesystem::absolute(o.out).lexically_normal().string();
  const std::string tasks = std::to_string(o.tasks);
  std::string script = "#!/bin/bash\n";
  script += "#SBATCH --job-name=ocp-campaign-" + std::to_string(o.seed) + "\n";
  script += "#SBATCH --array=0-" + std::to_string(o.tasks - 1) + "\n";
  script += "#SBATCH --cpus-per-task=" + std::to_string(o.jobs) + "\n";
  script += "#SBATCH --output=" + shell_quoted(slurm_pattern_literal(out) + "/shard-%a.log") + "\n";
  if (!o.partition.empty()) script += "#SBATCH --partition=" + shell_quoted(sbatch_literal(o.partition)) + "\n";
  script += "# Task i runs shard i/" + tasks + " into the folder --out names below, in shard-i (a folder every\n";
  script += "# node sees); `ocp_campaign merge` joins them. Exit 1 of a task means a world failed, not the task.\n";
  script += ": \"${SLURM_ARRAY_TASK_ID:?run this as a Slurm array task (sbatch)}\"\n";
  script += "exec " + shell_quoted(executable) + " run --seed " + std::to_string(o.seed) + " --worlds " +
            std::to_string(o.worlds) + " --profile " + shell_quoted(slurm_profile_argument(o.profile)) + " -j " +
            std::to_string(o.jobs) + " --shard \"$SLURM_ARRAY_TASK_ID/" + tasks + "\" --quiet --out " + shell_quoted(out) +
            "/shard-\"$SLURM_ARRAY_TASK_ID\"" + passed_on_options(o) + "\n";
  return script;
}

namespace {

std::string first_output_line(const std::string& text) { return text.substr(0, text.find('\n')); }

// The job's tasks still queued or running, from `squeue` (empty once the array is gone).
// nullopt: squeue failed; `error` says why.
std::optional<std::string> queued_tasks(const std::string& job, std::string& error) {
  const auto [queued, ok] = capture("squeue -h -j " + job + " -o %T 2>&1");
  if (queued.find("Invalid job id") != std::string::npos) return std::string();   // purged: done
  if (!ok) {
    error = first_output_line(queued);
    return std::nullopt;
  }
  std::string states;
  for (const char c : queued) states += c == '\n' ? ' ' : c;
  while (!states.empty() && states.back() == ' ') states.pop_back();
  return states;
}


// The profile, and the Slurm commands on PATH: an exit code when one is missing.
std::optional<int> check_before_submitting(const SlurmOptions& o) {
  try {   // a bad profile is one message here, not one failed task per shard
    const std::string& p = o.profile;
    load_profile(p.find('/') == std::string::npos && p.find('.') == std::string::npos ? shipped_profile_path(p) : p);
  } catch (const ProfileError& error) {
    std::cerr << "ocp_campaign slurm: " << error.what() << "\n";
    return exit_usage;
  }
  for (const char* tool : {"sbatch", "squeue"}) {
    if (!on_path(tool)) {
      std::cerr << "ocp_campaign slurm: '" << tool
                << "' is not on PATH (install slurm-client, or start a local cluster with scripts/slurm-local start)\n";
      return exit_usage;
    }
  }
  return std::nullopt;
}

// Writes the script into the output folder, cleared of an earlier run's shards; its path, or
// nullopt when it cannot be written.
std::optional<std::filesystem::path> write_script(const SlurmOptions& o, const std::filesystem::path& out,
                                                  const std::string& script) {
  namespace fs = std::filesystem;
  std::error_code error_code;
  fs::create_directories(out, error_code);
  // Shards of an earlier run in the same folder would be merged as if this run wrote them.
  for (int task = 0; task < o.tasks; ++task) {
    fs::remove_all(out / ("shard-" + std::to_string(task)), error_code);
    fs::remove(out / ("shard-" + std::to_string(task) + ".log"), error_code);
  }
  const fs::path script_path = out / "campaign.sbatch";
  std::ofstream(script_path) << script;
  if (!fs::exists(script_path)) {
    std::cerr << "ocp_campaign slurm: cannot write " << script_path.string() << "\n";
    return std::nullopt;
  }
  return script_path;
}

// Polls squeue until the job array has left the queue (nullopt), or gives the exit code of
// Ctrl-C, a controller that stops answering, or --timeout (the job is cancelled then).
std::optional<int> wait_for_job(const SlurmOptions& o, const std::string& job, const std::function<double()>& elapsed) {
  cli::install_interrupt_handlers();
  int failures_in_a_row = 0;
  std::string last_states;
  for (;;) {
    if (cli::interrupt_requested()) {
      capture("scancel " + job + " 2>&1");
      std::cerr << "interrupted: cancelled job " << job << "\n";
      return cli::exit_interrupted;
    }
    std::string error;
    const auto states = queued_tasks(job, error);
    if (!states) {
      // A loaded controller can time out once; a dead one keeps failing.
      if (++failures_in_a_row >= 5) {
        std::cerr << "ocp_campaign slurm: squeue failed 5 times in a row (is slurmctld reachable?): " << error << "\n";
        return exit_usage;
      }
    } else {
      failures_in_a_row = 0;
      if (states->empty()) return std::nullopt;
      if (*states != last_states) std::cerr << "job " << job << ": " << *states << "\n";
      last_states = *states;
    }
    if (elapsed() > o.timeout_seconds) {
      capture("scancel " + job + " 2>&1");
      std::cerr << "ocp_campaign slurm: job " << job << " still queued or running after " << o.timeout_seconds
                << " s (--timeout); cancelled it\n";
      return exit_usage;
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(o.poll_seconds));
  }
}

// `ocp_campaign merge` of every task's shard; a task that left no summary is an error.
int merge_shards(const SlurmOptions& o, const std::string& executable, const std::filesystem::path& out) {
  std::string merge = shell_quoted(executable) + " merge --out " + shell_quoted(out.string());
  for (int task = 0; task < o.tasks; ++task) {
    const std::filesystem::path shard = out / ("shard-" + std::to_string(task));
    if (!std::filesystem::exists(shard / "summary.json")) {
      std::cerr << "ocp_campaign slurm: task " << task << " left no summary.json (see " << out.string() << "/shard-"
                << task << ".log)\n";
      return exit_usage;
    }
    merge += " " + shell_quoted(shard.string());
  }
  const int status = std::system(merge.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : exit_usage;
}

}  // namespace

int run_slurm(const SlurmOptions& o) {
  const std::string executable = self_executable();
  std::string script;
  try {
    script = sbatch_script(o, executable);
  } catch (const std::invalid_argument& error) {
    std::cerr << "ocp_campaign slurm: " << error.what() << "\n";
    return exit_usage;
  }
  if (o.print_only) {
    std::cout << script;
    return 0;
  }
  if (auto exit_code = check_before_submitting(o)) return *exit_code;
  const std::filesystem::path out = std::filesystem::absolute(o.out).lexically_normal();
  const auto script_path = write_script(o, out, script);
  if (!script_path) return exit_usage;
  const auto start = std::chrono::steady_clock::now();
  const auto [submitted, ok] = capture("sbatch --parsable " + shell_quoted(script_path->string()) + " 2>&1");
  const std::string job = submitted.substr(0, submitted.find_first_of(";\n"));
  if (!ok || job.empty() || job.find_first_not_of("0123456789") != std::string::npos) {
    std::cerr << "ocp_campaign slurm: sbatch failed (is slurmctld reachable?): " << submitted << "\n";
    return exit_usage;
  }
  std::cerr << "submitted job array " << job << " (" << o.tasks << " tasks, script " << script_path->string()
            << "); polling squeue\n";
  const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  if (auto exit_code = wait_for_job(o, job, elapsed)) return *exit_code;
  std::cerr << "job " << job << " done after " << elapsed() << " s; merging\n";
  return merge_shards(o, executable, out);
}

}  // namespace ocp::campaign
