#pragma once
// How efficiently a campaign ran: what `ocp_campaign run` prints at its end and writes to
// efficiency.json beside the results (never into summary.json, which depends on nothing but
// the seeds). Workers are threads of this process (campaign.cpp); a --client campaign's
// vehicle clients are child processes. So CPU is the process's own (every thread: the
// workers, the world generation, the progress line; getrusage) plus the clients' (each one's
// process group, read from /proc when it is stopped), against the simulated time of the
// worlds that finished.
#include <cstddef>
#include <string>

#include "campaign/campaign.hpp"

namespace ocp::campaign {

struct Efficiency {
  std::size_t worlds = 0;
  int workers = 1;
  double wall_seconds = 0;
  double simulated_seconds = 0;
  double process_cpu_seconds = 0;    // RUSAGE_SELF: all threads, user + system
  double children_cpu_seconds = 0;   // the client processes of a --client campaign
  double world_cpu_seconds = 0;      // the workers' thread clocks inside the worlds alone

  double cpu_seconds() const { return process_cpu_seconds + children_cpu_seconds; }
  double worlds_per_second() const { return wall_seconds > 0 ? static_cast<double>(worlds) / wall_seconds : 0; }
  double worlds_per_second_per_worker() const { return worlds_per_second() / workers; }
  double simulated_per_cpu_second() const { return cpu_seconds() > 0 ? simulated_seconds / cpu_seconds() : 0; }
  // Flat as workers are added when nothing is shared between them (docs/benchmarks.md).
  double cpu_ms_per_world() const { return worlds > 0 ? 1e3 * cpu_seconds() / static_cast<double>(worlds) : 0; }
  double world_cpu_ms_per_world() const {
    return worlds > 0 ? 1e3 * world_cpu_seconds / static_cast<double>(worlds) : 0;
  }
};

Efficiency efficiency_of(const CampaignRun& run);
// Two lines for the terminal.
std::string efficiency_text(const Efficiency& efficiency);
// One JSON object (efficiency.json).
std::string efficiency_json(const Efficiency& efficiency);

}  // namespace ocp::campaign
