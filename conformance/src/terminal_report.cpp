#include <fmt/format.h>

#include <algorithm>
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

std::string verdict_counts(const RunSummary& summary) {
  std::map<Verdict, int> counts;
  int must_failed = 0;
  for (const CaseResult& result : summary.results) {
    ++counts[result.verdict];
    must_failed += result.verdict == Verdict::failed && result.info.tier == Tier::must;
  }
  return fmt::format("{} case{} in {:.1f} s: {} OK, {} NON-STRICT, {} INFORMATIONAL, {} FAILED ({} of them MUST)",
                     summary.results.size(), summary.results.size() == 1 ? "" : "s", summary.duration_ms / 1000.0,
                     counts[Verdict::ok], counts[Verdict::non_strict], counts[Verdict::informational],
                     counts[Verdict::failed], must_failed);
}

std::string interrupted_text(const RunSummary& summary) {
  return fmt::format("{} of {} case{} finished before Ctrl-C; the rest have no verdict", summary.results.size(),
                     summary.cases_selected, summary.cases_selected == 1 ? "" : "s");
}

std::vector<NamedCause> named_causes(const RunSummary& summary) {
  std::vector<NamedCause> causes;
  for (const CaseResult& result : summary.results) {
    if (result.cause.empty()) continue;
    auto found =
        std::find_if(causes.begin(), causes.end(), [&](const NamedCause& c) { return c.cause == result.cause; });
    if (found == causes.end()) found = causes.insert(causes.end(), NamedCause{result.cause, {}});
    found->case_ids.push_back(result.info.id);
  }
  return causes;
}

void print_summary(std::ostream& out, const ReportContext& report) {
  const RunSummary& summary = *report.summary;
  // A harness error before any case finished has no verdicts to count: it alone is the news.
  if (!summary.harness_error.empty() && summary.results.empty()) {
    out << "\nHARNESS ERROR: " << summary.harness_error << "\n";
    return;
  }
  out << "\n" << verdict_counts(summary) << "\n";
  for (const NamedCause& cause : named_causes(summary)) {
    std::string ids;
    for (const std::string& id : cause.case_ids) ids += (ids.empty() ? "" : ", ") + id;
    out << "Cause found: " << cause.cause << "\n    (in " << ids << ")\n";
  }
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
  if (summary.interrupted) out << "interrupted: " << interrupted_text(summary) << "\n";
  if (!summary.harness_error.empty()) out << "HARNESS ERROR: " << summary.harness_error << "\n";
}

}  // namespace ocp::conformance
