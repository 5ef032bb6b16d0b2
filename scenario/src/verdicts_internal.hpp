#pragma once
// What the verdict files share (verdicts.cpp, verdicts_window.cpp, verdicts_delivery.cpp): the
// run being judged, and the one rule for a run cut short.
#include <string>
#include <vector>

#include "scenario/metrics.hpp"
#include "scenario/verdicts.hpp"

namespace ocp::scenario {

struct JudgeContext {
  const Scenario& scenario;
  const RunResult& run;
  const Observations& observations;

  // Not judged: the run stopped at `run.ran`, before what this verdict needs had happened.
  void cut_short(Verdict& v) const {
    v.passed = false;
    v.interrupted = true;
    v.actual = "not judged: the run was interrupted at " + format_seconds(run.ran) + " of " +
               format_seconds(scenario.duration) + " (so far: " + v.actual + ")";
  }
  // Whether the run got past `time` (a window's end, an instant).
  bool ran_past(SimTime time) const { return !run.interrupted || time < run.ran; }
  // The fault's intervals on one vehicle, or nullptr when it was never raised there.
  const std::vector<Interval>* intervals(const std::string& vehicle, FaultId fault) const {
    const auto found = observations.faults.find({vehicle, fault});
    return found == observations.faults.end() ? nullptr : &found->second;
  }
};

// Equal as JSON values (1.0 == 1, key order aside); false when either is not JSON.
bool same_json_value(const std::string& a, const std::string& b);

// "388.5ms", "3.74s": durations as people write them.
std::string verdict_ms_text(Micros duration);

void judge_fault_never(const JudgeContext& context, const FaultNeverExpectation& e, Verdict& v);
void judge_fault_always(const JudgeContext& context, const FaultAlwaysExpectation& e, Verdict& v);
void judge_refusal(const JudgeContext& context, const RefusesToStartExpectation& e, Verdict& v);
void judge_delivery(const JudgeContext& context, const DeliveryExpectation& e, Verdict& v);
void judge_event(const JudgeContext& context, const EventExpectation& e, Verdict& v);
void judge_feedback(const JudgeContext& context, const FeedbackExpectation& e, Verdict& v);

}  // namespace ocp::scenario
