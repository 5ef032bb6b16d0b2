// What the campaign oracle costs (issue #21): the same generated worlds run by the scenario
// runner in virtual time with and without the Oracle attached, in one process (compare the two
// as a ratio of one run: the machine is shared). One-vehicle 60 s worlds of the
// default profile's draws (campaign/profiles/bench-1v60s.yaml), no trace, as a campaign runs
// them. Counters: simulated seconds per CPU second, per world.
//   build/bench/campaign_bench --benchmark_min_time=3s
#include <benchmark/benchmark.h>

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
    for (std::uint64_t index = 0; index < 64; ++index) made.push_back(campaign::generate_world(profile, 1, index));
    return made;
  }();
  return worlds;
}

void run_worlds(benchmark::State& state, bool with_oracle) {
  const auto& worlds = bench_worlds();
  std::size_t next = 0;
  double simulated = 0;
  for (auto _ : state) {
    const scenario::Scenario& world = worlds[next++ % worlds.size()];
    scenario::RunOptions options;
    options.trace = false;
    std::optional<campaign::Oracle> oracle;
    if (with_oracle) {
      oracle.emplace(world);
      options.on_built = [&](World& built) { oracle->attach(built); };
      options.on_finished = [&](World& built) { oracle->finish(built); };
    }
    benchmark::DoNotOptimize(scenario::run_scenario(world, options).executor_events);
    simulated += static_cast<double>(world.duration.count()) / 1e6;
  }
  state.counters["simulated_s_per_cpu_s"] = benchmark::Counter(simulated, benchmark::Counter::kIsRate);
}

void BM_CampaignWorld_WithOracle(benchmark::State& state) { run_worlds(state, true); }
void BM_CampaignWorld_WithoutOracle(benchmark::State& state) { run_worlds(state, false); }

BENCHMARK(BM_CampaignWorld_WithoutOracle)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();
BENCHMARK(BM_CampaignWorld_WithOracle)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

}  // namespace
