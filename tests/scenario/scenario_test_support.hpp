#pragma once
// Helpers for the scenario engine tests: parse inline YAML, run it, find a verdict.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scenario/parse.hpp"
#include "scenario/runner.hpp"
#include "scenario/verdicts.hpp"

namespace ocp::scenario::test {

struct Outcome {
  Scenario scenario;
  RunResult run;
  std::vector<Verdict> verdicts;
};

inline Outcome run_text(const std::string& yaml, RunOptions options = {}) {
  Outcome outcome{parse_scenario(yaml, "inline.yaml"), {}, {}};
  outcome.run = run_scenario(outcome.scenario, options);
  outcome.verdicts = evaluate(outcome.scenario, outcome.run);
  return outcome;
}

// The one verdict of a scenario with a single expectation.
inline const Verdict& only(const Outcome& outcome) {
  EXPECT_EQ(outcome.verdicts.size(), 1u);
  return outcome.verdicts.front();
}

// One vehicle, a 20 ms link, the drive script; `rest` adds timeline and expect.
inline std::string one_vehicle(const std::string& rest, const std::string& duration = "6s") {
  return "seed: 4\nduration: " + duration +
         "\nworld:\n  gamepad: drive\n  vehicles:\n    - name: truck-1\n      link: {delay: 20ms}\n" + rest;
}

}  // namespace ocp::scenario::test
