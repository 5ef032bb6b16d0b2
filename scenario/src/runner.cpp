// One scenario run (runner.hpp); virtual time here, real time in runner_realtime.cpp. Not VirtualWorld: its TraceRecorder would
// listen to every bus even without a trace, and every event would be built; here the trace
// listens only when asked for, and the Observer only to the buses it needs.
#include "scenario/runner.hpp"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <fstream>
#include <memory>

#include "ocp/virtual_executor.hpp"
#include "run_world.hpp"
#include "scenario/parse.hpp"
#include "timeline.hpp"
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

bool expects_refusal(const Scenario& scenario) {
  return std::any_of(scenario.expectations.begin(), scenario.expectations.end(), [](const Expectation& expectation) {
    return std::holds_alternative<RefusesToStartExpectation>(expectation.kind);
  });
}

bool needs_link_events(const Scenario& scenario) {
  for (const Expectation& expectation : scenario.expectations) {
    if (const auto* threshold = std::get_if<ThresholdExpectation>(&expectation.kind)) {
      if (threshold->metric != "latency_ms" && threshold->metric != "echo_delay_ms" &&
          threshold->metric != "control_gap_ms") {
        return true;
      }
    }
  }
  return false;
}

namespace {

constexpr Micros ping_sample_period{100'000};

void add(RouteCounters& out, const DirectionCounters& counters) {
  out.sent = counters.sent;
  out.delivered = counters.delivered;
  out.dropped = counters.dropped;
}

// What the expectations need decoded: control frames in delivery windows, feedback fields.
ObserverOptions observer_options(const Scenario& scenario, bool link_events) {
  ObserverOptions options{needs_controller_check(scenario), link_events, {}, {}};
  for (const Expectation& expectation : scenario.expectations) {
    if (const auto* delivery = std::get_if<DeliveryExpectation>(&expectation.kind)) {
      options.delivery_windows.push_back({delivery->vehicle, delivery->after, delivery->after + delivery->within});
    }
    if (const auto* feedback = std::get_if<FeedbackExpectation>(&expectation.kind)) {
      for (const FeedbackCheck& check : feedback->checks) {
        const bool watched = std::any_of(options.feedback_watches.begin(), options.feedback_watches.end(), [&](const FeedbackWatch& w) {
          return w.vehicle == feedback->vehicle && w.field == check.field;
        });
        if (!watched) options.feedback_watches.push_back({feedback->vehicle, check.field});
      }
    }
  }
  return options;
}

}  // namespace

RunResult run_world(Executor& executor, const Scenario& scenario, const RunOptions& options,
                    bool deterministic_keys, const ClockDriver& drive) {
  const auto wall_start = std::chrono::steady_clock::now();
  const std::clock_t cpu_start = std::clock();
  RunResult result;
  result.seed = options.seed.value_or(scenario.seed);
  result.duration = scenario.duration;

  WorldConfig config = world_config(scenario, result.seed);
  config.deterministic_keys = deterministic_keys;
  // Log lines are not part of a scenario's outcome (the trace is): they go nowhere.
  World world(executor, config, make_null_sink());
  std::ofstream trace_file;   // before the recorder: it writes here until it is destroyed
  std::unique_ptr<TraceRecorder> trace;
  if (options.trace) {
    TraceOptions trace_options;
    trace_options.frame_payloads = options.trace_payloads;
    trace_options.keep_lines = options.trace_in_memory && options.trace_file.empty();
    if (!options.trace_file.empty()) {
      trace_file.open(options.trace_file, std::ios::binary | std::ios::trunc);
      if (!trace_file) throw HarnessError("cannot write " + options.trace_file);
      trace_options.stream = &trace_file;
    }
    trace = std::make_unique<TraceRecorder>(world.events(), trace_options);
  }
  // With a trace every event is built anyway: the Observer may as well count link messages.
  const bool link_events = options.trace || needs_link_events(scenario);
  Observer observer(world, observer_options(scenario, link_events));
  const SimTime origin = executor.now();
  observer.set_origin(origin);
  if (options.on_built) options.on_built(world);
  if (auto status = world.start(); !status) {
    if (!expects_refusal(scenario)) throw HarnessError("the world did not start: " + status.error().message());
    result.refused_to_start = status.error().message();
    result.observations = observer.observations();
    return result;
  }
  observer.attach_parts();
  apply_gamepad(world.player().gamepad(), scenario.gamepad, executor.now());
  OperatorClient operator_client(world, scenario.operator_client);
  if (scenario.operator_client.connect) operator_client.start();
  const auto keep_alive = schedule_timeline(world, scenario.timeline, scenario.duration, result.fired, origin,
                                            scenario.operator_client.connect ? &operator_client : nullptr);
  // Ping is not on the event stream; sample what the Player shows, for the report's plot.
  Observations& observations = observer.observations();
  PeriodicTimer ping_sampler(executor, ping_sample_period, [&](SimTime now) {
    for (const auto& [vehicle, feedback] : world.player().last_shared().vehicle_feedback) {
      observations.vehicles[vehicle].ping_ms.add(now - origin, static_cast<double>(feedback.ping_latency_ms));
    }
  });
  ping_sampler.start(executor.now() + ping_sample_period);
  const SimTime stopped = std::min(drive(world, origin + scenario.duration), origin + scenario.duration);
  result.ran = stopped - origin;
  result.interrupted = result.ran < scenario.duration;
  if (options.on_finished) options.on_finished(world);
  ping_sampler.stop();
  operator_client.stop();
  if (!link_events) {
    // Message counts for the summary, from the links themselves (no expectation needs them).
    for (const std::string& vehicle : world.vehicles()) {
      VehicleObservations& out = observer.observations().vehicles[vehicle];
      add(out.to_streamer, world.link(vehicle).to_streamer().counters());
      add(out.to_player, world.link(vehicle).to_player().counters());
    }
  }
  result.observations = observer.observations();
  if (trace_file.is_open()) {
    trace_file.close();
    if (!trace_file) throw HarnessError("cannot write " + options.trace_file + " (disk full?)");
  }
  if (trace) {
    result.trace_jsonl = trace->jsonl();
    result.trace_digest = trace->digest();
    result.trace_lines = trace->lines();
  }
  world.stop();
  result.cpu_seconds = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  result.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  return result;
}

namespace {

// The ceiling on events per simulated second (ParseLimits::max_events_per_s), counted in the
// run's own seconds ([0 s, 1 s), [1 s, 2 s), …): crossing it stops the run at once.
class EventCeiling {
 public:
  EventCeiling(std::uint64_t ceiling, SimTime origin) : ceiling_(ceiling), origin_(origin) {}
  void count(SimTime now) {
    const std::int64_t second = (now - origin_).count() / 1'000'000;
    if (second != second_) {
      second_ = second;
      events_ = 0;
    }
    if (++events_ > ceiling_) {
      throw HarnessError("more than " + std::to_string(ceiling_) + " events in the simulated second from " +
                         std::to_string(second) + "s: over the ceiling of events per simulated second (a control_period, "
                         "ping_period, camera fps or fleet this busy runs away; --max-events-per-s raises it)");
    }
  }

 private:
  std::uint64_t ceiling_;
  SimTime origin_;
  std::int64_t second_ = 0;
  std::uint64_t events_ = 0;
};

}  // namespace

RunResult run_scenario(const Scenario& scenario, const RunOptions& options) {
  VirtualExecutor executor;
  RunResult result = run_world(executor, scenario, options, true, [&](World&, SimTime end) {
    // In slices, to look at the interrupt flag in between; the events run are the same as in one
    // go (every event due by the slice's end runs, in order), so the trace is too.
    constexpr Micros slice{100'000};
    EventCeiling ceiling(parse_limits().max_events_per_s, executor.now());
    while (executor.now() < end) {
      if (options.interrupted && options.interrupted()) return executor.now();
      const SimTime slice_end = std::min(end, executor.now() + slice);
      while (executor.next_deadline() <= slice_end) {
        executor.step();
        ceiling.count(executor.now());
      }
      executor.run_until(slice_end);
    }
    return end;
  });
  result.executor_events = executor.events_run();
  return result;
}

RunResult run_scenario_driven(const Scenario& scenario, const RunOptions& options, const VirtualDriver& drive) {
  VirtualExecutor executor;
  RunResult result = run_world(executor, scenario, options, true, [&](World& world, SimTime end) { return drive(world, executor, end); });
  result.executor_events = executor.events_run();
  return result;
}

}  // namespace ocp::scenario
