// One scenario run in virtual time (runner.hpp).
#include "scenario/runner.hpp"

#include <chrono>

#include "timeline.hpp"
#include "world/virtual_world.hpp"
#include "world_setup.hpp"

namespace ocp::scenario {

bool needs_controller_check(const Scenario& scenario) {
  for (const Expectation& expectation : scenario.expectations) {
    if (const auto* invariant = std::get_if<InvariantExpectation>(&expectation.kind)) {
      if (invariant->invariant == Invariant::default_controller_during_control_fault) return true;
    }
  }
  return false;
}

RunResult run_scenario(const Scenario& scenario, const RunOptions& options) {
  const auto wall_start = std::chrono::steady_clock::now();
  RunResult result;
  result.seed = options.seed.value_or(scenario.seed);
  result.duration = scenario.duration;

  TraceOptions trace;
  trace.keep_lines = options.trace;
  trace.frame_payloads = options.trace_payloads;
  if (!options.trace) {
    // Digest only, and of the cheap events: the full stream is for trace.jsonl.
    trace.frames = false;
    trace.link_messages = false;
    trace.latency_samples = false;
  }
  VirtualWorld sim(world_config(scenario, result.seed), trace);
  Observer observer(sim.world().events(), ObserverOptions{needs_controller_check(scenario)});
  if (auto status = sim.start(); !status) {
    throw HarnessError("the world did not start: " + status.error().message());
  }
  apply_gamepad(sim.world().player().gamepad(), scenario.gamepad, sim.now());
  const auto keep_alive = schedule_timeline(sim.world(), scenario.timeline, scenario.duration, result.fired);
  sim.run_until(scenario.duration);
  result.executor_events = sim.executor().events_run();
  result.observations = observer.observations();
  result.trace_jsonl = sim.trace().jsonl();
  result.trace_digest = sim.trace().digest();
  result.trace_lines = sim.trace().lines();
  sim.world().stop();
  result.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  return result;
}

}  // namespace ocp::scenario
