#include <fmt/format.h>

#include <map>

#include "conformance/reports.hpp"

namespace ocp::conformance {

void print_case_line(std::ostream& out, const CaseResult& result) {
  out << fmt::format("[{:^13}] {:<14} {:<6} {:>6.0f} ms  {}\n", verdict_name(result.verdict), result.info.id,
                     tier_name(result.info.tier), result.duration_ms, result.info.title);
  if (result.verdict == Verdict::ok) return;
  out << "    Requirement: " << result.info.requirement << " [" << result.info.source << "]\n";
  for (const std::string& e : result.info.expected) out << "    Expected:    " << e << "\n";
  out << "    Actual:      " << result.actual << "\n";
  if (!result.client_log_path.empty()) out << "    Client log:  " << result.client_log_path << "\n";
}

void print_summary(std::ostream& out, const ReportContext& report) {
  const RunSummary& summary = *report.summary;
  std::map<Verdict, int> counts;
  int must_failed = 0;
  for (const CaseResult& result : summary.results) {
    ++counts[result.verdict];
    must_failed += result.verdict == Verdict::failed && result.info.tier == Tier::must;
  }
  out << fmt::format("\n{} cases in {:.1f} s: {} OK, {} NON-STRICT, {} INFORMATIONAL, {} FAILED ({} of them MUST)\n",
                     summary.results.size(), summary.duration_ms / 1000.0, counts[Verdict::ok], counts[Verdict::non_strict],
                     counts[Verdict::informational], counts[Verdict::failed], must_failed);
  if (report.baseline != nullptr) {
    const BaselineDiff& d = *report.baseline;
    auto list = [](const std::vector<std::string>& ids) {
      std::string text;
      for (const auto& id : ids) {
        text += ' ';
        text += id;
      }
      return text.empty() ? std::string(" none") : text;
    };
    out << "Baseline: new failures:" << list(d.new_failures) << "\n"
        << "          still failing (expected):" << list(d.still_failing) << "\n"
        << "          fixed (remove from the baseline):" << list(d.fixed) << "\n";
  }
  if (!summary.harness_error.empty()) out << "HARNESS ERROR: " << summary.harness_error << "\n";
}

}  // namespace ocp::conformance
