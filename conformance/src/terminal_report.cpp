#include <fmt/format.h>

#include <map>

#include "conformance/reports.hpp"

namespace ocp::conformance {

void print_case_line(std::ostream& out, const CaseResult& r) {
  out << fmt::format("[{:^13}] {:<14} {:<6} {:>6.0f} ms  {}\n", verdict_name(r.verdict), r.info.id,
                     tier_name(r.info.tier), r.duration_ms, r.info.title);
  if (r.verdict == Verdict::ok) return;
  out << "    Requirement: " << r.info.requirement << " [" << r.info.source << "]\n";
  for (const std::string& e : r.info.expected) out << "    Expected:    " << e << "\n";
  out << "    Actual:      " << r.actual << "\n";
  if (!r.client_log_path.empty()) out << "    Client log:  " << r.client_log_path << "\n";
}

void print_summary(std::ostream& out, const ReportContext& c) {
  const RunSummary& s = *c.summary;
  std::map<Verdict, int> counts;
  int must_failed = 0;
  for (const CaseResult& r : s.results) {
    ++counts[r.verdict];
    must_failed += r.verdict == Verdict::failed && r.info.tier == Tier::must;
  }
  out << fmt::format("\n{} cases in {:.1f} s: {} OK, {} NON-STRICT, {} INFORMATIONAL, {} FAILED ({} of them MUST)\n",
                     s.results.size(), s.duration_ms / 1000.0, counts[Verdict::ok], counts[Verdict::non_strict],
                     counts[Verdict::informational], counts[Verdict::failed], must_failed);
  if (c.baseline != nullptr) {
    const BaselineDiff& d = *c.baseline;
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
  if (!s.harness_error.empty()) out << "HARNESS ERROR: " << s.harness_error << "\n";
}

}  // namespace ocp::conformance
