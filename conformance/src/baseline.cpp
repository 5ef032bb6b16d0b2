#include "conformance/baseline.hpp"

#include <fstream>
#include <sstream>

#include "ocp/bounded_file.hpp"
#include "ocp/interrupt.hpp"

namespace ocp::conformance {

Result<Baseline> load_baseline(const std::string& path) {
  const auto text = read_bounded_file(path, file_kinds::baseline);
  if (!text) return Error{text.error().code, "cannot read baseline " + text.error().detail};
  std::istringstream in(*text);
  Baseline baseline;
  std::string line;
  while (std::getline(in, line)) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::istringstream words(line);
    std::string id;
    if (words >> id) baseline.insert(id);  // "id [anything]": only the id counts
  }
  return baseline;
}

std::string baseline_text(const std::vector<CaseResult>& results) {
  std::string out = "# ocp_conformance baseline: cases expected to fail\n";
  for (const CaseResult& result : results) {
    if (result.verdict == Verdict::failed) out += result.info.id + "  # " + result.info.title + "\n";
  }
  return out;
}

BaselineDiff diff_baseline(const Baseline& baseline, const std::vector<CaseResult>& results) {
  BaselineDiff diff;
  for (const CaseResult& result : results) {
    const bool expected = baseline.count(result.info.id) > 0;
    if (result.verdict == Verdict::failed) {
      (expected ? diff.still_failing : diff.new_failures).push_back(result.info.id);
    } else if (expected) {
      diff.fixed.push_back(result.info.id);
    }
  }
  return diff;
}

int exit_code(const std::vector<CaseResult>& results, const Baseline* baseline) {
  for (const CaseResult& result : results) {
    if (result.verdict != Verdict::failed || result.info.tier != Tier::must) continue;
    if (baseline != nullptr && baseline->count(result.info.id) > 0) continue;
    return 1;
  }
  return 0;
}

int run_exit_code(const RunSummary& summary, const Baseline* baseline) {
  if (summary.interrupted) return ocp::cli::exit_interrupted;
  if (!summary.harness_error.empty()) return ocp::cli::exit_usage_error;
  return exit_code(summary.results, baseline);
}

}  // namespace ocp::conformance
