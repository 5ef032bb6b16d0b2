// Verdicts over a window of the run (verdicts_internal.hpp): a fault never active in it, a
// fault active all through it; and the world that must refuse to start.
#include <algorithm>

#include "verdicts_internal.hpp"

namespace ocp::scenario {

void judge_fault_never(const JudgeContext& context, const FaultNeverExpectation& e, Verdict& v) {
  v.kind = "fault_never";
  const SimTime end = e.until.value_or(context.scenario.duration);
  v.expected = e.from > SimTime{0} || e.until ? "never active" : "never raised";
  if (e.from > SimTime{0}) v.expected += " from " + format_seconds(e.from);
  if (e.until) v.expected += " until " + format_seconds(*e.until);
  std::size_t raises = 0;
  std::optional<std::pair<SimTime, std::string>> first;
  for (const auto& [key, list] : context.observations.faults) {
    if (key.second != e.fault || (e.vehicle && key.first != *e.vehicle)) continue;
    for (const Interval& interval : list) {
      // Raised before `from` but still active after it counts too: it was active then. Raised
      // at or after `until` does not: the window was over.
      if (interval.end && *interval.end <= e.from) continue;
      if (e.until && interval.start >= end) continue;
      ++raises;
      if (!first || interval.start < first->first) first = {interval.start, key.first};
    }
  }
  v.passed = raises == 0;
  v.actual = raises == 0 ? "never raised"
                         : "raised " + std::to_string(raises) + " time(s), first on " + first->second + " at " +
                               format_seconds(first->first);
  if (v.passed && !context.ran_past(end - Micros{1})) context.cut_short(v);
}

void judge_fault_always(const JudgeContext& context, const FaultAlwaysExpectation& e, Verdict& v) {
  v.kind = "fault_always";
  const SimTime end = e.until.value_or(context.scenario.duration);
  v.expected = "active on " + e.vehicle + " from " + e.from_label + " until " + (e.until ? e.until_label : "the end");
  const std::vector<Interval>* list = context.intervals(e.vehicle, e.fault);
  const Interval* covering = nullptr;
  const Interval* first_in_window = nullptr;
  if (list != nullptr) {
    for (const Interval& interval : *list) {
      if (interval.end && *interval.end <= e.from) continue;
      if (interval.start >= end) break;
      if (first_in_window == nullptr) first_in_window = &interval;
      if (interval.start <= e.from && (!interval.end || *interval.end >= end)) covering = &interval;
    }
  }
  if (covering != nullptr) {
    v.passed = true;
    v.actual = "active from " + format_seconds(covering->start) +
               (covering->end ? " until " + format_seconds(*covering->end) : " to the end");
    if (!context.ran_past(end - Micros{1})) context.cut_short(v);
    return;
  }
  if (first_in_window == nullptr) {
    v.actual = "not active in the window";
  } else if (first_in_window->start > e.from) {
    v.actual = "not active at " + format_seconds(e.from) + " (first raised at " + format_seconds(first_in_window->start) + ")";
  } else {
    v.actual = "cleared at " + format_seconds(*first_in_window->end) + ", inside the window";
  }
  if (!context.ran_past(end - Micros{1}) && first_in_window == nullptr) context.cut_short(v);
}

void judge_refusal(const JudgeContext& context, const RefusesToStartExpectation& e, Verdict& v) {
  v.kind = "refuses_to_start";
  v.expected = "the world refuses to start: \"" + e.reason + "\"";
  if (!context.run.refused_to_start) {
    v.actual = "the world started";
    return;
  }
  v.passed = context.run.refused_to_start->find(e.reason) != std::string::npos;
  v.actual = "refused: " + *context.run.refused_to_start;
}

}  // namespace ocp::scenario
