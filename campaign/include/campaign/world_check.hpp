#pragma once
// One world under the oracle: run it through the scenario runner in virtual time with the
// Oracle attached; for the sampled share, run it a second time with the trace on and compare
// the two trace digests (determinism).
#include <cstdint>
#include <string>
#include <vector>

#include "campaign/oracle.hpp"
#include "scenario/model.hpp"
#include "scenario/runner.hpp"

namespace ocp::campaign {

struct WorldOutcome {
  std::uint64_t index = 0;
  std::uint64_t seed = 0;
  Micros duration{0};
  int vehicles = 0;
  int timeline_events = 0;
  std::vector<Violation> violations;
  std::uint64_t violation_count = 0;
  bool determinism_checked = false;
  bool liveness_checked = false;
  std::string error;        // the world refused to start (a generator bug): counts as a failure
  double cpu_seconds = 0;   // not part of any compared output
  double client_cpu_seconds = 0;   // --client: the client processes' (sim_app::ClientProcess::cpu_seconds)
  std::uint64_t events = 0;
  std::vector<std::string> hazards;   // a client world's (client_world.hpp, hazards_in)
  bool failed() const { return violation_count > 0 || !error.empty(); }
};

struct CheckOptions {
  bool determinism = false;   // run twice, compare trace digests
};

WorldOutcome check_world(const scenario::Scenario& scenario, const CheckOptions& options = {});

// The scenario runner's own run of the same world, with a trace (for report.html).
scenario::RunResult run_for_report(const scenario::Scenario& scenario);

}  // namespace ocp::campaign
