#pragma once
// Expectations × observations → one verdict each, with what was expected and what happened.
#include <string>
#include <vector>

#include "scenario/model.hpp"
#include "scenario/runner.hpp"

namespace ocp::scenario {

struct Verdict {
  std::string title;      // the expectation, one line
  std::string kind;       // fault_edge, fault_never, fault_state, threshold, invariant
  Mark mark;
  bool passed = false;
  // The run was cut short (Ctrl-C) before this could be judged: not passed, not failed either.
  bool interrupted = false;
  std::string expected;   // "within [1s, 6s]"
  std::string actual;     // "raised 2.31s after ramp_up (at 14.8s)"
};

// A run cut short judges what it can: an edge or a delivery seen, a window or an instant it
// got past, a violation. Whatever needs the rest of the timeline (a never, a threshold, an
// invariant that saw nothing wrong, a window still open) is marked interrupted.
std::vector<Verdict> evaluate(const Scenario& scenario, const RunResult& run);
bool all_passed(const std::vector<Verdict>& verdicts);
bool any_interrupted(const std::vector<Verdict>& verdicts);

}  // namespace ocp::scenario
