#pragma once
// A campaign: N worlds from one campaign seed, on -j worker threads (each world its own
// VirtualWorld), optionally one shard of them (every N-th world), stopping early when asked
// (Ctrl-C) with the finished worlds kept.
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "campaign/client_world.hpp"
#include "campaign/profile.hpp"
#include "campaign/world_check.hpp"

namespace ocp::campaign {

struct Shard {
  std::uint32_t index = 0, count = 1;   // worlds i with i % count == index
  bool contains(std::uint64_t world) const { return world % count == index; }
};

struct CampaignOptions {
  std::uint64_t seed = 1;
  std::uint64_t worlds = 100;
  Profile profile;
  int jobs = 1;
  Shard shard;
  std::function<bool()> stop;   // true: take no new world (Ctrl-C)
  // Set: every world runs in real time against this vehicle client (client_world.hpp). A world
  // whose client cannot be started ends the campaign (CampaignRun::harness_error).
  std::optional<ClientRun> client;
};

struct Progress {
  std::uint64_t done = 0, total = 0, failures = 0;
  double wall_seconds = 0;
};

struct CampaignRun {
  std::vector<WorldOutcome> outcomes;   // by world index
  bool interrupted = false;
  std::string harness_error;   // --client: the client could not be started (exit 2)
  double wall_seconds = 0, cpu_seconds = 0;   // cpu: the worlds' own, on their workers' thread clocks
  // getrusage over the run: the whole process (all threads); and the client processes of a
  // --client campaign, each world's read from its process groups (WorldOutcome::
  // client_cpu_seconds: a `/bin/sh -c` client is reaped by init, so RUSAGE_CHILDREN misses
  // it). efficiency.hpp turns these into the closing figures.
  double process_cpu_seconds = 0, children_cpu_seconds = 0;
  int workers = 1;
};

// World `index` of the campaign, checked as `options` say (virtual time, or against the client).
WorldOutcome check_campaign_world(const CampaignOptions& options, std::uint64_t index);

// Is world `index` of this campaign one of the sampled share that runs twice?
bool determinism_sampled(const Profile& profile, std::uint64_t campaign_seed, std::uint64_t index);

// `on_progress` is called from the workers (serialised) after every world.
CampaignRun run_campaign(const CampaignOptions& options, const std::function<void(const Progress&)>& on_progress = {});

}  // namespace ocp::campaign
