// JUnit XML (reports.hpp): one testsuite per run, one testcase per expectation.
#include "ocp/build_info.hpp"
#include "scenario/reports.hpp"
#include "sim_app/report_text.hpp"

namespace ocp::scenario {
namespace {

std::string xml(std::string_view text) { return report::markup_escape(text); }

}  // namespace

std::string junit_xml(const std::vector<RunReport>& reports, bool interrupted) {
  std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites";
  out += interrupted ? " interrupted=\"true\">\n" : ">\n";
  for (const RunReport& report : reports) {
    std::size_t failures = 0, skipped = 0;
    for (const Verdict& verdict : report.verdicts) {
      failures += verdict.passed || verdict.interrupted ? 0 : 1;
      skipped += verdict.interrupted ? 1 : 0;
    }
    // Repeated runs (--repeat, --seed) of one file stay apart: the seed joins the name.
    std::string name = report.scenario->name;
    if (report.run->seed != report.scenario->seed) name += " (seed " + std::to_string(report.run->seed) + ")";
    out += "  <testsuite name=\"" + xml(name) + "\" file=\"" + xml(report.scenario->path) + "\" tests=\"" +
           std::to_string(report.verdicts.size()) + "\" failures=\"" + std::to_string(failures) + "\" skipped=\"" +
           std::to_string(skipped) + "\" time=\"" +
           std::to_string(report.run->wall_seconds) + "\">\n";
    out += "    <properties><property name=\"ocp_sim_version\" value=\"" + xml(build_info::version_line()) +
           "\"/><property name=\"seed\" value=\"" + std::to_string(report.run->seed) +
           "\"/><property name=\"reproduce\" value=\"" + xml(report.reproduce) + "\"/>" +
           (report.run->interrupted ? "<property name=\"interrupted\" value=\"true\"/>" : "") + "</properties>\n";
    for (const Verdict& verdict : report.verdicts) {
      out += "    <testcase classname=\"" + xml(report.scenario->name) + "\" name=\"" + xml(verdict.title) + "\"";
      if (verdict.passed) {
        out += "/>\n";
      } else if (verdict.interrupted) {
        out += ">\n      <skipped message=\"" + xml(verdict.actual) + "\"/>\n    </testcase>\n";
      } else {
        out += ">\n      <failure message=\"expected " + xml(verdict.expected) + ", actual " + xml(verdict.actual) +
               "\">" + xml(report.scenario->path + ":" + std::to_string(verdict.mark.line) + " reproduce: " + report.reproduce) +
               "</failure>\n    </testcase>\n";
      }
    }
    out += "  </testsuite>\n";
  }
  return out + "</testsuites>\n";
}

}  // namespace ocp::scenario
