#include <fmt/format.h>

#include "conformance/reports.hpp"
#include "ocp/build_info.hpp"
#include "sim_app/report_text.hpp"

namespace ocp::conformance {

std::string junit_xml(const ReportContext& report) {
  const RunSummary& summary = *report.summary;
  std::size_t failures = 0;
  for (const CaseResult& result : summary.results) failures += result.verdict == Verdict::failed;
  std::string xml = fmt::format(
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites><testsuite name=\"ocp_conformance.{}\" tests=\"{}\" "
      "failures=\"{}\" errors=\"{}\" time=\"{:.3f}\">\n",
      report.suite, summary.results.size(), failures, int(!summary.harness_error.empty()) + int(summary.interrupted),
      summary.duration_ms / 1000.0);
  xml += fmt::format("  <properties><property name=\"ocp_sim_version\" value=\"{}\"/></properties>\n",
                     report::markup_escape(build_info::version_line()));
  for (const CaseResult& result : summary.results) {
    xml += fmt::format("  <testcase classname=\"{}.{}\" name=\"{}\" time=\"{:.3f}\">\n", report.suite,
                       tier_name(result.info.tier), report::markup_escape(result.info.id), result.duration_ms / 1000.0);
    std::string detail = "Requirement: " + result.info.requirement + "\n";
    for (const auto& e : result.info.expected) detail += "Expected: " + e + "\n";
    detail += "Actual: " + result.actual;
    if (result.verdict == Verdict::failed) {
      xml += fmt::format("    <failure message=\"{}\">{}</failure>\n", report::markup_escape(result.actual),
                         report::markup_escape(detail));
    } else {
      xml += fmt::format("    <system-out>{}: {}</system-out>\n", verdict_name(result.verdict),
                         report::markup_escape(detail));
    }
    xml += "  </testcase>\n";
  }
  if (!summary.harness_error.empty()) {
    xml += fmt::format("  <testcase classname=\"{}\" name=\"harness\"><error message=\"{}\"/></testcase>\n",
                       report.suite, report::markup_escape(summary.harness_error));
  }
  if (summary.interrupted) {
    xml += fmt::format("  <testcase classname=\"{}\" name=\"interrupted\"><error message=\"{}\"/></testcase>\n",
                       report.suite, report::markup_escape(interrupted_text(summary)));
  }
  xml += "</testsuite></testsuites>\n";
  return xml;
}

std::string case_list(const std::vector<CaseInfo>& cases, bool markdown) {
  std::string out;
  if (!markdown) {
    for (const CaseInfo& c : cases) out += fmt::format("{:<14} {:<6} {}\n", c.id, tier_name(c.tier), c.title);
    return out;
  }
  auto cell = [](std::string text) {
    std::string escaped;
    for (char ch : text) escaped += ch == '|' ? std::string("\\|") : std::string(1, ch);
    return escaped;
  };
  out += "| id | tier | case | requirement (source) | accepted outcomes | timeout | fails against |\n";
  out += "|---|---|---|---|---|---|---|\n";
  for (const CaseInfo& c : cases) {
    std::string expected;
    for (std::size_t i = 0; i < c.expected.size(); ++i) {
      expected += i ? "<br>" : "";
      expected += cell(c.expected[i]);
    }
    out += fmt::format("| `{}` | {} | {} | {} ({}) | {} | {} s | {} |\n", c.id, tier_name(c.tier), cell(c.title),
                       cell(c.requirement), cell(c.source), expected, c.timeout.count() / 1000, cell(c.broken_by));
  }
  return out;
}

}  // namespace ocp::conformance
