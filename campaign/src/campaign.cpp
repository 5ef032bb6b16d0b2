// The campaign runner (campaign.hpp): workers pull world indices from one counter.
#include "campaign/campaign.hpp"

#include <sys/resource.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <chrono>
#include <mutex>
#include <thread>

#include "campaign/generator.hpp"
#include "sim_app/proc_stat.hpp"
#include "world/seeds.hpp"

namespace ocp::campaign {

bool determinism_sampled(const Profile& profile, std::uint64_t campaign_seed, std::uint64_t index) {
  const std::uint64_t draw = derive_seed(campaign_seed, "determinism:" + std::to_string(index));
  return static_cast<double>(draw >> 11) * 0x1.0p-53 < profile.determinism_share;
}

WorldOutcome check_campaign_world(const CampaignOptions& options, std::uint64_t index) {
  const scenario::Scenario world = generate_world(options.profile, options.seed, index);
  if (options.client) {
    return check_world_with_client(for_external_client(world, index, options.client->max_world), index, *options.client,
                                   options.stop);
  }
  WorldOutcome outcome = check_world(world, {determinism_sampled(options.profile, options.seed, index)});
  outcome.index = index;
  return outcome;
}

namespace {

// User + system CPU of `who` (RUSAGE_SELF: every thread of this process).
double cpu_seconds_of(int who) {
  rusage usage{};
  getrusage(who, &usage);
  return sim_app::cpu_seconds(usage);
}

// Every world frees all it allocated and the next world allocates it again. With more than one
// worker, glibc gave each worker arena's freed top back to the kernel after every world
// (madvise) and faulted it in again: 7 times the page faults of one worker, about 90 a world
// (docs/benchmarks.md, "Campaign scaling"), and in a process with many threads each give-back
// also interrupts every core running one of them (TLB shootdown). So arenas keep up to 64 MiB
// free, and blocks up to 32 MiB come from them rather than from mmap (fixed thresholds: glibc's
// dynamic ones moved per block freed). Process-wide, set once; peak memory is unchanged.
void keep_freed_memory_for_the_next_world() {
#if defined(__GLIBC__)
  static std::once_flag once;
  std::call_once(once, [] {
    mallopt(M_TRIM_THRESHOLD, 64 << 20);
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
  });
#endif
}

}  // namespace

CampaignRun run_campaign(const CampaignOptions& options, const std::function<void(const Progress&)>& on_progress) {
  keep_freed_memory_for_the_next_world();
  const auto wall_start = std::chrono::steady_clock::now();
  const double process_cpu_start = cpu_seconds_of(RUSAGE_SELF);
  std::vector<std::uint64_t> indices;
  for (std::uint64_t i = 0; i < options.worlds; ++i) {
    if (options.shard.contains(i)) indices.push_back(i);
  }
  std::vector<WorldOutcome> outcomes(indices.size());
  std::vector<bool> finished(indices.size(), false);
  std::atomic<std::size_t> next{0};
  std::mutex mutex;
  Progress progress;
  progress.total = indices.size();
  bool interrupted = false;
  std::string harness_error;

  auto worker = [&] {
    for (;;) {
      if (options.stop && options.stop()) {
        const std::lock_guard lock(mutex);
        interrupted = true;
        return;
      }
      const std::size_t slot = next.fetch_add(1);
      if (slot >= indices.size()) return;
      WorldOutcome outcome = check_campaign_world(options, indices[slot]);
      const std::lock_guard lock(mutex);
      if (options.client && !outcome.error.empty()) {   // the client, not the world: stop here
        if (harness_error.empty()) harness_error = outcome.error;
        next = indices.size();
        return;
      }
      outcomes[slot] = std::move(outcome);
      finished[slot] = true;
      ++progress.done;
      if (outcomes[slot].failed()) ++progress.failures;
      progress.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
      if (on_progress) on_progress(progress);
    }
  };
  const int jobs = std::max(1, options.jobs);
  std::vector<std::thread> threads;
  for (int j = 1; j < jobs; ++j) threads.emplace_back(worker);
  worker();
  for (std::thread& thread : threads) thread.join();

  CampaignRun run;
  run.interrupted = interrupted && progress.done < progress.total;
  run.harness_error = harness_error;
  for (std::size_t slot = 0; slot < indices.size(); ++slot) {
    if (!finished[slot]) continue;
    run.cpu_seconds += outcomes[slot].cpu_seconds;
    run.children_cpu_seconds += outcomes[slot].client_cpu_seconds;
    run.outcomes.push_back(std::move(outcomes[slot]));
  }
  run.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  run.process_cpu_seconds = cpu_seconds_of(RUSAGE_SELF) - process_cpu_start;
  run.workers = jobs;
  return run;
}

}  // namespace ocp::campaign
