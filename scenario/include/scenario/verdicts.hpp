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
  std::string expected;   // "within [1s, 6s]"
  std::string actual;     // "raised 2.31s after ramp_up (at 14.8s)"
};

std::vector<Verdict> evaluate(const Scenario& scenario, const RunResult& run);
bool all_passed(const std::vector<Verdict>& verdicts);

}  // namespace ocp::scenario
