// `ocp_campaign slurm` (slurm.hpp).
#include "campaign/slurm.hpp"

#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <thread>

#include "ocp/cli_checks.hpp"

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

std::string quoted(const std::string& text) {
  std::string out = "'";
  for (const char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string self_executable() {
  std::error_code error;
  const auto path = std::filesystem::read_symlink("/proc/self/exe", error);
  return error ? std::string("ocp_campaign") : path.string();
}

}  // namespace

void add_slurm_options(CLI::App& app, SlurmOptions& options) {
  app.add_option("--seed", options.seed, "campaign seed")->check(cli::whole())->capture_default_str();
  app.add_option("--worlds", options.worlds, "worlds in the campaign")->check(cli::whole(1, 10'000'000))->capture_default_str();
  app.add_option("--profile", options.profile, "generator profile: default, calm, or a YAML file")->capture_default_str();
  app.add_option("--tasks", options.tasks, "array tasks (shards)")->check(CLI::Range(1, 10'000))->capture_default_str();
  app.add_option("-j,--jobs", options.jobs, "worker threads per task (--cpus-per-task)")->check(CLI::Range(1, 256))->capture_default_str();
  app.add_option("--out", options.out, "results folder (shards in shard-<i>/, merged at the top)")->capture_default_str();
  app.add_option("--partition", options.partition, "Slurm partition (default: the cluster's)");
  app.add_option("--poll", options.poll_seconds, "seconds between squeue polls")->check(cli::real(0.05, 600))->capture_default_str();
  app.add_option("--timeout", options.timeout_seconds, "give up waiting after this many seconds")
      ->check(cli::real(1, 7 * 86400))->capture_default_str();
  app.add_flag("--print-only", options.print_only, "print the sbatch script and exit");
}

std::string sbatch_script(const SlurmOptions& o, const std::string& executable) {
  const std::string out = std::filesystem::absolute(o.out).string();
  std::string script = "#!/bin/bash\n";
  script += "#SBATCH --job-name=ocp-campaign-" + std::to_string(o.seed) + "\n";
  script += "#SBATCH --array=0-" + std::to_string(o.tasks - 1) + "\n";
  script += "#SBATCH --cpus-per-task=" + std::to_string(o.jobs) + "\n";
  script += "#SBATCH --output=" + out + "/shard-%a.log\n";
  if (!o.partition.empty()) script += "#SBATCH --partition=" + o.partition + "\n";
  script += "# Task i runs shard i/" + std::to_string(o.tasks) +
            ": ocp_campaign reads SLURM_ARRAY_TASK_ID and SLURM_ARRAY_TASK_COUNT.\n";
  script += "exec " + quoted(executable) + " run --seed " + std::to_string(o.seed) + " --worlds " +
            std::to_string(o.worlds) + " --profile " + quoted(o.profile) + " -j " + std::to_string(o.jobs) +
            " --quiet --out " + quoted(out) + "/shard-$SLURM_ARRAY_TASK_ID\n";
  return script;
}

int run_slurm(const SlurmOptions& o) {
  const std::string executable = self_executable();
  const std::string script = sbatch_script(o, executable);
  if (o.print_only) {
    std::cout << script;
    return 0;
  }
  for (const char* tool : {"sbatch", "squeue"}) {
    if (!on_path(tool)) {
      std::cerr << "ocp_campaign slurm: '" << tool
                << "' is not on PATH (install slurm-client, or start a local cluster with scripts/slurm-local start)\n";
      return exit_usage;
    }
  }
  namespace fs = std::filesystem;
  fs::create_directories(o.out);
  const fs::path script_path = fs::absolute(o.out) / "campaign.sbatch";
  std::ofstream(script_path) << script;
  const auto [submitted, ok] = capture("sbatch --parsable " + quoted(script_path.string()) + " 2>&1");
  const std::string job = submitted.substr(0, submitted.find_first_of(";\n"));
  if (!ok || job.empty() || job.find_first_not_of("0123456789") != std::string::npos) {
    std::cerr << "ocp_campaign slurm: sbatch failed (is slurmctld reachable?): " << submitted << "\n";
    return exit_usage;
  }
  std::cerr << "submitted job array " << job << " (" << o.tasks << " tasks); waiting\n";
  const auto start = std::chrono::steady_clock::now();
  for (;;) {
    const auto [queued, reachable] = capture("squeue -h -j " + job + " -o %T 2>&1");
    if (!reachable && queued.find("Invalid job id") == std::string::npos) {
      std::cerr << "ocp_campaign slurm: squeue failed (is slurmctld reachable?): " << queued << "\n";
      return exit_usage;
    }
    if (queued.find_first_not_of(" \n") == std::string::npos || queued.find("Invalid job id") != std::string::npos) break;
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > o.timeout_seconds) {
      std::cerr << "ocp_campaign slurm: job " << job << " still queued or running after " << o.timeout_seconds << " s\n";
      return exit_usage;
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(o.poll_seconds));
  }
  std::string merge = quoted(executable) + " merge --out " + quoted(o.out);
  for (int task = 0; task < o.tasks; ++task) {
    const fs::path shard = fs::path(o.out) / ("shard-" + std::to_string(task));
    if (!fs::exists(shard / "summary.json")) {
      std::cerr << "ocp_campaign slurm: task " << task << " left no summary.json (see " << o.out << "/shard-" << task
                << ".log)\n";
      return exit_usage;
    }
    merge += " " + quoted(shard.string());
  }
  const int status = std::system(merge.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : exit_usage;
}

}  // namespace ocp::campaign
