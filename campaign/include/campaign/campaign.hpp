#pragma once
// A campaign: N worlds from one campaign seed, on -j worker threads (each world its own
// VirtualWorld), optionally one shard of them (every N-th world), stopping early when asked
// (Ctrl-C) with the finished worlds kept.
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

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
};

struct Progress {
  std::uint64_t done = 0, total = 0, failures = 0;
  double wall_seconds = 0;
};

struct CampaignRun {
  std::vector<WorldOutcome> outcomes;   // by world index
  bool interrupted = false;
  double wall_seconds = 0, cpu_seconds = 0;
};

// Is world `index` of this campaign one of the sampled share that runs twice?
bool determinism_sampled(const Profile& profile, std::uint64_t campaign_seed, std::uint64_t index);

// `on_progress` is called from the workers (serialised) after every world.
CampaignRun run_campaign(const CampaignOptions& options, const std::function<void(const Progress&)>& on_progress = {});

}  // namespace ocp::campaign
