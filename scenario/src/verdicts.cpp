// Verdicts (verdicts.hpp): each expectation kind judged from the Observer's observations.
#include "scenario/verdicts.hpp"

#include <algorithm>

#include <rapidjson/document.h>

#include "ocp/flap_summariser.hpp"
#include "scenario/metrics.hpp"
#include "verdicts_internal.hpp"

namespace ocp::scenario {

std::string verdict_ms_text(Micros duration) {
  if (duration >= Micros{1'000'000}) return format_seconds(duration);
  return format_number(static_cast<double>(duration.count()) / 1000.0) + "ms";
}

namespace {

bool active_at(const JudgeContext& context, const std::string& vehicle, FaultId fault, SimTime at) {
  const auto* list = context.intervals(vehicle, fault);
  if (list == nullptr) return false;
  return std::any_of(list->begin(), list->end(), [&](const Interval& interval) {
    return interval.start <= at && (!interval.end || at < *interval.end);
  });
}

class Judge {
 public:
  Judge(const Scenario& scenario, const RunResult& run) : context_{scenario, run, run.observations} {}

  void cut_short(Verdict& v) const { context_.cut_short(v); }
  bool ran_past(SimTime time) const { return context_.ran_past(time); }

  void operator()(const FaultEdgeExpectation& e, Verdict& v) const {
    const char* edge = e.raised ? "raised" : "cleared";
    v.kind = "fault_edge";
    std::string window;
    if (e.min > Micros{0}) {
      window.append("[").append(verdict_ms_text(e.min)).append(", ").append(verdict_ms_text(e.max)).append("]");
    } else {
      window.append("≤ ").append(verdict_ms_text(e.max));
    }
    v.expected.append(edge).append(" within ").append(window).append(" after ").append(e.after_label);
    std::optional<SimTime> found;
    const std::vector<Interval>* list = context_.intervals(e.vehicle, e.fault);
    if (list != nullptr) {
      for (const Interval& interval : *list) {
        const std::optional<SimTime> at = e.raised ? std::optional(interval.start) : interval.end;
        if (at && *at >= e.after) {
          found = at;
          break;
        }
      }
    }
    // An edge after the anchor says nothing about the event when the fault was already doing
    // it before: such an expectation fails, saying so, instead of "raised 0ms after".
    const std::string before = list == nullptr ? "" : state_before(*list, e);
    if (!found) {
      v.actual = std::string("never ") + edge + " after " + e.after_label;
      if (!e.raised && active_at(context_, e.vehicle, e.fault, scenario().duration)) {
        v.actual += run().interrupted ? " (still active when the run was interrupted)" : " (still active at the end)";
      }
      if (!before.empty()) v.actual = before + "; " + v.actual;
      if (!ran_past(e.after + e.max)) cut_short(v);
      return;
    }
    const Micros delay = *found - e.after;
    v.passed = before.empty() && delay >= e.min && delay <= e.max;
    v.actual = std::string(edge) + " " + verdict_ms_text(delay) + " after " + e.after_label + " (at " + format_seconds(*found) + ")";
    if (!before.empty()) v.actual = before + "; next " + v.actual;
  }

  // "already flapping before ramp_up (raised 6 times in the 5s before it)", "already active at
  // ramp_up (raised at 3.2s)", or "" when the fault was quiet. Flapping as the product's logs
  // call it (FlapSummariser's defaults); "active" matters only to a raise.
  static std::string state_before(const std::vector<Interval>& list, const FaultEdgeExpectation& e) {
    const FlapSummariser::Options flap;
    std::size_t raises = 0;
    std::optional<SimTime> active_since;
    for (const Interval& interval : list) {
      if (interval.start >= e.after) break;
      if (interval.start >= e.after - flap.window) ++raises;
      if (!interval.end || *interval.end > e.after) active_since = interval.start;
    }
    if (raises >= flap.raises_to_flap) {
      return "already flapping before " + e.after_label + " (raised " + std::to_string(raises) + " times in the " +
             format_seconds(flap.window) + " before it)";
    }
    if (e.raised && active_since) return "already active at " + e.after_label + " (raised at " + format_seconds(*active_since) + ")";
    return "";
  }

  void operator()(const FaultNeverExpectation& e, Verdict& v) const { judge_fault_never(context_, e, v); }
  void operator()(const FaultAlwaysExpectation& e, Verdict& v) const { judge_fault_always(context_, e, v); }
  void operator()(const RefusesToStartExpectation& e, Verdict& v) const { judge_refusal(context_, e, v); }
  void operator()(const DeliveryExpectation& e, Verdict& v) const { judge_delivery(context_, e, v); }
  void operator()(const EventExpectation& e, Verdict& v) const { judge_event(context_, e, v); }
  void operator()(const FeedbackExpectation& e, Verdict& v) const { judge_feedback(context_, e, v); }

  void operator()(const FaultStateExpectation& e, Verdict& v) const {
    v.kind = "fault_state";
    std::vector<std::string> on = e.active_on, off = e.inactive_on;
    if (e.every_vehicle_but_active) {
      std::optional<std::string> active;
      for (const auto& [time, vehicle] : observations_.active_vehicle) {
        if (time <= e.at) active = vehicle;
      }
      for (const VehicleSpec& spec : scenario().world.vehicles) {
        if (spec.monitor) continue;
        (active && spec.name == *active ? off : on).push_back(spec.name);
      }
    }
    std::string expected, actual;
    v.passed = true;
    auto check = [&](const std::vector<std::string>& names, bool want) {
      for (const std::string& name : names) {
        const bool is = active_at(context_, name, e.fault, e.at);
        expected += name + (want ? "=active " : "=inactive ");
        actual += name + (is ? "=active " : "=inactive ");
        v.passed = v.passed && is == want;
      }
    };
    check(on, true);
    check(off, false);
    if (!expected.empty()) expected.pop_back();
    if (!actual.empty()) actual.pop_back();
    v.expected = expected;
    v.actual = actual;
    if (!ran_past(e.at)) cut_short(v);
  }

  void operator()(const ThresholdExpectation& e, Verdict& v) const {
    v.kind = "threshold";
    v.expected = e.text;
    std::optional<double> value;
    std::string resolution_note;
    if (is_counter_metric(e.metric)) {
      value = counter_value(observations_, e.metric, e.vehicle, e.aggregate);
    } else {
      const ValueHistogram values = series_values(observations_, e.metric, e.vehicle);
      value = aggregate(values, e.aggregate, e.percentile);
      if (values.resolution_ms() > 0 && (e.aggregate == "med" || e.aggregate.rfind("p(", 0) == 0)) {
        resolution_note = " (within " + format_number(values.resolution_ms()) + " ms: over " +
                          std::to_string(ValueHistogram::distinct_capacity) + " distinct values)";
      }
    }
    if (!value) {
      v.actual = e.aggregate + " = no samples";
      if (run().interrupted) cut_short(v);
      return;
    }
    const double x = *value;
    if (e.op == "<") v.passed = x < e.value;
    else if (e.op == "<=") v.passed = x <= e.value;
    else if (e.op == ">") v.passed = x > e.value;
    else if (e.op == ">=") v.passed = x >= e.value;
    else if (e.op == "==") v.passed = x == e.value;
    else v.passed = x != e.value;
    v.actual = e.aggregate + " = " + format_number(x) + resolution_note;
    if (run().interrupted) cut_short(v);
  }

  void operator()(const InvariantExpectation& e, Verdict& v) const {
    v.kind = "invariant";
    if (e.invariant == Invariant::default_controller_during_control_fault) {
      std::uint64_t checked = 0;
      for (const auto& [name, data] : observations_.vehicles) checked += data.control_frames_checked;
      const auto& violations = observations_.controller_violations;
      v.expected = "only default or null controllers under control-path faults";
      if (checked == 0) {
        v.actual = "no control frame was sent under a control-path fault: nothing checked";
        if (run().interrupted) cut_short(v);
      } else if (violations.empty()) {
        v.passed = true;
        v.actual = std::to_string(checked) + " control frames checked, all default or null";
        if (run().interrupted) cut_short(v);
      } else {
        v.actual = std::to_string(observations_.controller_violation_count) + " of " + std::to_string(checked) + " frames violated; first at " +
                   format_seconds(violations.front().time) + " on " + violations.front().vehicle + ": " + violations.front().detail;
      }
      return;
    }
    const auto& violations = observations_.stale_pair_violations;
    v.expected = "no pair from before a reconnect echoed on the new connection";
    if (observations_.reconnects == 0) {
      v.actual = "no reconnect happened: nothing checked";
      if (run().interrupted) cut_short(v);
    } else if (violations.empty()) {
      v.passed = true;
      v.actual = std::to_string(observations_.reconnects) + " reconnect(s), no stale pair";
      if (run().interrupted) cut_short(v);
    } else {
      v.actual = std::to_string(observations_.stale_pair_violation_count) + " stale pair(s); first at " + format_seconds(violations.front().time) +
                 " on " + violations.front().vehicle + ": " + violations.front().detail;
    }
  }

 private:
  const Scenario& scenario() const { return context_.scenario; }
  const RunResult& run() const { return context_.run; }

  JudgeContext context_;
  const Observations& observations_ = context_.observations;
};

}  // namespace

std::vector<Verdict> evaluate(const Scenario& scenario, const RunResult& run) {
  Judge judge(scenario, run);
  std::vector<Verdict> verdicts;
  for (const Expectation& expectation : scenario.expectations) {
    Verdict verdict;
    verdict.title = expectation.title;
    verdict.mark = expectation.mark;
    std::visit([&](const auto& kind) { judge(kind, verdict); }, expectation.kind);
    verdicts.push_back(std::move(verdict));
  }
  return verdicts;
}

bool any_interrupted(const std::vector<Verdict>& verdicts) {
  return std::any_of(verdicts.begin(), verdicts.end(), [](const Verdict& v) { return v.interrupted; });
}

bool all_passed(const std::vector<Verdict>& verdicts) {
  return std::all_of(verdicts.begin(), verdicts.end(), [](const Verdict& v) { return v.passed; });
}

}  // namespace ocp::scenario
