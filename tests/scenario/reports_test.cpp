// report.html embeds exactly summary.json; JUnit has one testcase per expectation with the
// failures saying expected vs actual; the tool's exit codes are 0 / 1 / 2.
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "scenario/reports.hpp"
#include "scenario_test_support.hpp"

namespace ocp::scenario {
namespace {

const std::string story = test::one_vehicle(R"(timeline:
  - {at: 1s, name: unplug, gamepad: unplug}
  - {at: 2s, name: replug, gamepad: replug}
expect:
  faults:
    - {fault: InputLost, raised: {after: unplug, within: 20ms}, cleared: {after: replug, within: 20ms}}
  thresholds:
    latency_ms: ["p(99) < 5"]
)", "3s");

TEST(ScenarioReports, HtmlEmbedsTheSummary) {
  const auto outcome = test::run_text(story);
  RunReport report{&outcome.scenario, &outcome.run, outcome.verdicts, "ocp_scenario run inline.yaml --seed 4"};
  const std::string summary = summary_json(report);
  const std::string html = report_html(report, summary);
  const std::string open = "<script type=\"application/json\" id=\"summary\">\n";
  const auto begin = html.find(open);
  ASSERT_NE(begin, std::string::npos);
  const auto end = html.find("</script>", begin);
  std::string embedded = html.substr(begin + open.size(), end - begin - open.size());
  for (std::size_t at = 0; (at = embedded.find("<\\/", at)) != std::string::npos;) embedded.replace(at, 3, "</");
  EXPECT_EQ(embedded, summary);
  EXPECT_NE(html.find("<svg"), std::string::npos);
  EXPECT_NE(html.find("<polyline"), std::string::npos);
  EXPECT_EQ(html.find("http://", html.find("</svg>")), std::string::npos) << "no network references outside the SVG namespace";
  EXPECT_NE(summary.find("\"reproduce\": \"ocp_scenario run inline.yaml --seed 4\""), std::string::npos);
  EXPECT_NE(summary.find("\"p99\""), std::string::npos);
}

TEST(ScenarioReports, JunitOneCasePerExpectation) {
  const auto outcome = test::run_text(story);
  RunReport report{&outcome.scenario, &outcome.run, outcome.verdicts, "repro"};
  const std::string xml = junit_xml({report});
  EXPECT_NE(xml.find("tests=\"3\" failures=\"1\""), std::string::npos) << xml;
  EXPECT_NE(xml.find("<failure message=\"expected p(99) &lt; 5, actual p(99) = "), std::string::npos) << xml;
}

int run_tool(const std::string& arguments) {
  const int status = std::system((std::string(OCP_SCENARIO_PATH) + " " + arguments + " >/dev/null 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(ScenarioTool, ExitCodes) {
  const auto dir = std::filesystem::temp_directory_path() / ("ocp_scenario_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "fails.yaml") << story;
  std::ofstream(dir / "bad.yaml") << "seed: 1\nduration: 1s\nworld: {vehicles: [{name: a, wheels: 4}]}\nexpect: {}\n";
  const std::string out = " --out " + (dir / "out").string();
  EXPECT_EQ(run_tool("run " + std::string(OCP_SCENARIO_LIBRARY_DIR) + "/gamepad_unplug.yaml" + out), 0);
  EXPECT_EQ(run_tool("run " + (dir / "fails.yaml").string() + out + " --junit " + (dir / "j.xml").string()), 1);
  EXPECT_EQ(run_tool("run " + (dir / "bad.yaml").string() + out), 2);
  EXPECT_EQ(run_tool("run " + (dir / "fails.yaml").string() + " --list"), 0);
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "fails" / "report.html"));
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "fails" / "trace.jsonl"));
  EXPECT_TRUE(std::filesystem::exists(dir / "j.xml"));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ocp::scenario
