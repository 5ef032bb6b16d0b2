#pragma once
// The suite's outputs: terminal lines and summary, index.json, a self-contained HTML report
// (case matrix + per-case detail with the wire log), JUnit XML, and the case list as Markdown
// (docs/conformance.md is generated from it).
#include <ostream>
#include <string>
#include <vector>

#include "conformance/baseline.hpp"
#include "conformance/case.hpp"
#include "conformance/runner.hpp"

namespace ocp::conformance {

struct ReportContext {
  std::string suite = "vehicle";
  std::string client;  // the command, or "external client on port N"
  RunSummary const* summary = nullptr;
  BaselineDiff const* baseline = nullptr;  // null: no baseline given
};

// "16 cases in 21.3 s: 12 OK, 1 NON-STRICT, 0 INFORMATIONAL, 3 FAILED (3 of them MUST)".
std::string verdict_counts(const RunSummary& summary);
// "5 of 16 cases finished before Ctrl-C; the rest have no verdict".
std::string interrupted_text(const RunSummary& summary);

// Each named cause (Outcome::cause) once, with the cases that showed it, in case order.
struct NamedCause {
  std::string cause;
  std::vector<std::string> case_ids;
};
std::vector<NamedCause> named_causes(const RunSummary& summary);

// One line per case as it finishes; for every case that is not OK also Requirement,
// Expected (every accepted outcome) and Actual.
void print_case_line(std::ostream& out, const CaseResult& result);
void print_summary(std::ostream& out, const ReportContext& context);

std::string index_json(const ReportContext& context);
std::string html_report(const ReportContext& context);
std::string junit_xml(const ReportContext& context);
// --list: "id  TIER  title"; with markdown: the docs/conformance.md case table.
std::string case_list(const std::vector<CaseInfo>& cases, bool markdown);

// Entries of a wire log shown in reports: the first `head` and the last `tail` (big logs).
inline constexpr std::size_t wire_log_head = 300;
inline constexpr std::size_t wire_log_tail = 700;

}  // namespace ocp::conformance
