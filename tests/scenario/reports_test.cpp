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

// The link panels: a trace-driven uplink's delivered throughput and queueing delay over time,
// computed from the link events (the library's cellular collapse: 24 Mbit/s, 0.6 Mbit/s from
// 4 s to 10 s, under 12 Mbit/s of video).
TEST(ScenarioReports, TraceLinkThroughputAndQueueingDelayInTheReport) {
  const Scenario scenario = load_scenario(std::string(OCP_SCENARIO_LIBRARY_DIR) + "/cellular_uplink_collapse.yaml");
  const RunResult run = run_scenario(scenario, RunOptions{});
  const LinkSeries& up = run.observations.vehicles.at("truck-1").to_player_link;
  // Samples in [from, to) s: their mean, or (rate = true) the mean rate over the window, one
  // sample per 100 ms bucket with deliveries.
  const auto between = [](const PlotSeries& series, double from_s, double to_s, bool rate) {
    double sum = 0;
    int count = 0;
    for (const Sample& s : series.points()) {
      if (s.time >= SimTime{static_cast<std::int64_t>(from_s * 1e6)} && s.time < SimTime{static_cast<std::int64_t>(to_s * 1e6)}) {
        sum += s.value;
        ++count;
      }
    }
    if (rate) return sum * 0.1 / (to_s - from_s);
    return count == 0 ? -1.0 : sum / count;
  };
  EXPECT_NEAR(between(up.throughput_mbps, 1, 4, true), 12.1, 0.5);    // the video (and feedback) offered
  // At most the collapsed capacity, 0.6 Mbit/s of 1500-byte opportunities: each small feedback
  // message uses a whole one (Mahimahi's rule), so fewer bytes get through.
  EXPECT_LE(between(up.throughput_mbps, 5, 10, true), 0.6);
  EXPECT_GE(between(up.throughput_mbps, 5, 10, true), 0.2);
  EXPECT_GT(between(up.queueing_delay_ms, 6, 10, false), 1000.0);     // a full 100-packet queue: ~2 s
  EXPECT_LT(between(up.queueing_delay_ms, 12, 16, false), 30.0);      // drained: a frame's own packets only
  RunReport report{&scenario, &run, evaluate(scenario, run), "repro"};
  const std::string html = report_html(report, summary_json(report));
  EXPECT_NE(html.find("<title>throughput_mbps truck-1 to_player</title>"), std::string::npos);
  EXPECT_NE(html.find("<title>queueing_delay_ms truck-1 to_player</title>"), std::string::npos);
  EXPECT_NE(html.find("<title>throughput_mbps truck-1 to_streamer</title>"), std::string::npos);
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
