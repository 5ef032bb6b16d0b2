// One world under the oracle (world_check.hpp).
#include "campaign/world_check.hpp"

#include <time.h>

#include "world/world.hpp"

namespace ocp::campaign {

namespace {

// This thread's CPU time: with -j N workers the process clock would count every worker.
double thread_cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + static_cast<double>(now.tv_nsec) * 1e-9;
}

scenario::RunResult run_with_oracle(const scenario::Scenario& scenario, Oracle& oracle, bool trace) {
  scenario::RunOptions options;
  options.trace = trace;
  options.trace_in_memory = false;   // the digest is what is compared: a 1 h world holds no line
  options.on_built = [&](World& world) { oracle.attach(world); };
  options.on_finished = [&](World& world) { oracle.finish(world); };
  return scenario::run_scenario(scenario, options);
}

}  // namespace

WorldOutcome check_world(const scenario::Scenario& scenario, const CheckOptions& options) {
  WorldOutcome outcome;
  outcome.seed = scenario.seed;
  outcome.duration = scenario.duration;
  outcome.vehicles = static_cast<int>(scenario.world.vehicles.size());
  outcome.timeline_events = static_cast<int>(scenario.timeline.size());
  const double cpu_start = thread_cpu_seconds();
  try {
    Oracle oracle(scenario);
    const scenario::RunResult first = run_with_oracle(scenario, oracle, options.determinism);
    outcome.violations = oracle.violations();
    outcome.violation_count = oracle.violation_count();
    outcome.liveness_checked = oracle.liveness_checked();
    outcome.events = oracle.events_seen();
    if (options.determinism) {
      outcome.determinism_checked = true;
      Oracle again(scenario);
      const scenario::RunResult second = run_with_oracle(scenario, again, true);
      if (second.trace_digest != first.trace_digest || second.trace_lines != first.trace_lines) {
        ++outcome.violation_count;
        outcome.violations.push_back({Check::determinism, SimTime{0}, "",
                                      "two runs of the same world gave different traces (digest " +
                                          std::to_string(first.trace_digest) + " vs " +
                                          std::to_string(second.trace_digest) + ")",
                                      std::nullopt, false, std::nullopt});
      }
    }
  } catch (const scenario::HarnessError& error) {
    outcome.error = error.what();
  }
  outcome.cpu_seconds = thread_cpu_seconds() - cpu_start;
  return outcome;
}

scenario::RunResult run_for_report(const scenario::Scenario& scenario) {
  scenario::RunOptions options;
  options.trace = true;              // for the link events the report's panels draw
  options.trace_in_memory = false;
  return scenario::run_scenario(scenario, options);
}

}  // namespace ocp::campaign
