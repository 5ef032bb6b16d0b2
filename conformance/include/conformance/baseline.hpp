#pragma once
// Expected failures: a text file of case ids (one per line, '#' comments) a team knows its
// client fails today. The run is then judged against it: a failure in the baseline does not
// fail the run; a new failure does; a baseline entry that now passes is reported as fixed.
#include <set>
#include <string>
#include <vector>

#include "conformance/case.hpp"
#include "conformance/runner.hpp"
#include "ocp/error.hpp"

namespace ocp::conformance {

using Baseline = std::set<std::string>;

Result<Baseline> load_baseline(const std::string& path);
std::string baseline_text(const std::vector<CaseResult>& results);  // the failures of a run

struct BaselineDiff {
  std::vector<std::string> new_failures;   // failed now, not in the baseline
  std::vector<std::string> still_failing;  // failed now, in the baseline
  std::vector<std::string> fixed;          // in the baseline, ran, did not fail
};
BaselineDiff diff_baseline(const Baseline& baseline, const std::vector<CaseResult>& results);

// 0: every MUST case passed (or failed as the baseline expects); 1: otherwise.
int exit_code(const std::vector<CaseResult>& results, const Baseline* baseline);
// The whole run's: 130 interrupted (Ctrl-C), 2 harness error, else exit_code(results, baseline).
int run_exit_code(const RunSummary& summary, const Baseline* baseline);

}  // namespace ocp::conformance
