#pragma once
// Shrinking (docs/campaigns.md): a failing world reduced to a small one that still breaks the
// same invariant (the same Check, and for the fault model the same fault): vehicles, timeline
// events and start impairments are dropped and the duration shortened, one candidate at a time,
// each kept only when the oracle still finds that violation.
#include <functional>

#include "campaign/oracle.hpp"
#include "campaign/world_check.hpp"
#include "scenario/model.hpp"

namespace ocp::campaign {

struct ShrinkTarget {
  Check check = Check::fault_model;
  std::optional<FaultId> fault;
  static ShrinkTarget of(const Violation& violation) { return {violation.check, violation.fault}; }
  bool matches(const Violation& violation) const {
    return violation.check == check && (!fault || violation.fault == fault);
  }
};

struct ShrinkResult {
  scenario::Scenario scenario;
  Violation violation;   // the one the shrunk world shows
  int runs = 0;          // worlds run while shrinking
};

// `max_runs` bounds the work (each candidate is one world run). `check`: how a candidate runs
// (empty: check_world, in-process; a client world passes its own).
using WorldChecker = std::function<WorldOutcome(const scenario::Scenario&)>;
ShrinkResult shrink(const scenario::Scenario& failing, const ShrinkTarget& target, int max_runs = 300,
                    const WorldChecker& check = {});

// The shrunk world as a scenario a user can commit: expectations that say what the oracle
// found (a fault state at an instant, or the matching scenario invariant), and a header with
// the violation and the one-line command that reproduces it.
std::string regression_yaml(const ShrinkResult& shrunk, const std::string& repro_command);

}  // namespace ocp::campaign
