// What the campaign oracle costs (issue #21): 32 generated worlds, each run by the scenario
// runner in virtual time without and then with the Oracle attached, back to back (the machine
// is shared: compare as a ratio of one run). One-vehicle 60 s worlds of the default profile's
// draws (campaign/profiles/bench-1v60s.yaml), no trace, as a campaign runs them. Counters: the
// oracle's share of the CPU, simulated seconds per CPU second with and without it.
//   build/bench/campaign_bench
#include <benchmark/benchmark.h>

#include <time.h>

#include <optional>
#include <vector>

#include "campaign/generator.hpp"
#include "campaign/oracle.hpp"
#include "campaign/profile.hpp"
#include "scenario/runner.hpp"

namespace {

using namespace ocp;

const std::vector<scenario::Scenario>& bench_worlds() {
  static const std::vector<scenario::Scenario> worlds = [] {
    const campaign::Profile profile = campaign::load_profile(campaign::shipped_profile_path("bench-1v60s"));
    std::vector<scenario::Scenario> made;
    for (std::uint64_t index = 0; index < 32; ++index) made.push_back(campaign::generate_world(profile, 1, index));
    return made;
  }();
  return worlds;
}

double thread_cpu_now() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + static_cast<double>(now.tv_nsec) * 1e-9;
}

// CPU seconds of one world's run, with or without the oracle.
double world_cpu(const scenario::Scenario& world, bool with_oracle) {
  scenario::RunOptions options;
  options.trace = false;
  std::optional<campaign::Oracle> oracle;
  if (with_oracle) {
    oracle.emplace(world);
    options.on_built = [&](World& built) { oracle->attach(built); };
    options.on_finished = [&](World& built) { oracle->finish(built); };
  }
  const double start = thread_cpu_now();
  benchmark::DoNotOptimize(scenario::run_scenario(world, options).executor_events);
  return thread_cpu_now() - start;
}

// Each world runs without and then with the oracle, back to back, so noise hits both alike;
// the iteration time is both runs of every world.
void BM_OracleCost(benchmark::State& state) {
  const auto& worlds = bench_worlds();
  double without = 0, with = 0, simulated = 0;
  for (auto _ : state) {
    for (const scenario::Scenario& world : worlds) {
      without += world_cpu(world, false);
      with += world_cpu(world, true);
      simulated += static_cast<double>(world.duration.count()) / 1e6;
    }
  }
  state.counters["oracle_share_pct"] = 100.0 * (with - without) / without;
  state.counters["sim_s_per_cpu_s_with_oracle"] = simulated / with;
  state.counters["sim_s_per_cpu_s_without"] = simulated / without;
  state.counters["cpu_ms_per_world_with_oracle"] = 1000.0 * with / (simulated / 60.0);
}

BENCHMARK(BM_OracleCost)->Unit(benchmark::kSecond)->Iterations(2);

}  // namespace
