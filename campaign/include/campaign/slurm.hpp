#pragma once
// `ocp_campaign slurm`: the campaign as a Slurm job array (docs/campaigns.md). Writes an
// sbatch script whose task i runs shard i (ocp_campaign run reads SLURM_ARRAY_TASK_ID and
// SLURM_ARRAY_TASK_COUNT), submits it with `sbatch --parsable`, polls `squeue` until the array
// is gone, then merges the shards. --print-only prints the script for clusters with their own
// conventions. Slurm missing or unreachable: a message naming the command, exit 2.
#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>

namespace ocp::campaign {

struct SlurmOptions {
  std::uint64_t seed = 1;
  std::uint64_t worlds = 100;
  std::string profile = "default";
  int tasks = 4;           // array size = shards
  int jobs = 1;            // worker threads per task (--cpus-per-task)
  std::string out = "campaign-results";
  std::string partition;   // empty: the cluster's default
  double poll_seconds = 1.0;
  double timeout_seconds = 3600.0;
  bool print_only = false;
  // Passed on to every task's `ocp_campaign run` (empty / 0: not given, the run's default).
  std::string client;                 // --client CMD (its {port} stays for the task)
  std::string time;                   // --time virtual|real
  double max_world_seconds = 0;       // --max-world-seconds
  double world_timeout_seconds = 0;   // --world-timeout
  std::uint64_t max_events_per_s = 0; // --max-events-per-s
};

void add_slurm_options(CLI::App& app, SlurmOptions& options);
std::string sbatch_script(const SlurmOptions& options, const std::string& executable);
int run_slurm(const SlurmOptions& options);   // exit code

}  // namespace ocp::campaign
