// `trace:` in scenario files: resolved against the scenario file, shared by the directions that
// name the same file, and a bad trace is an error naming the trace's file and line.
#include <filesystem>
#include <fstream>

#include "ocp/delivery_trace.hpp"
#include "scenario_test_support.hpp"
#include "scratch_dir.hpp"

namespace ocp::scenario {
namespace {

namespace fs = std::filesystem;

class ScenarioLinkTrace : public ::testing::Test {
 protected:
  void SetUp() override { fs::create_directories(folder_ / "traces"); }
  void write(const std::string& name, const std::string& text) { std::ofstream(folder_ / name) << text; }
  std::string path(const std::string& name) const { return (folder_ / name).string(); }
  static std::string with_link(const std::string& link) {
    return "seed: 1\nduration: 2s\nworld:\n  vehicles:\n    - name: truck-1\n" + link +
           "expect: {invariants: [no_stale_pair_after_reconnect]}\n";
  }
  testing_support::ScratchDir scratch_{"ocp_link_trace_test"};
  fs::path folder_ = scratch_.path();
};

TEST_F(ScenarioLinkTrace, RelativeToTheScenarioFileAndSharedByBothDirections) {
  write("traces/lte.trace", "1\n1\n2\n");
  write("story.yaml", with_link("      link: {trace: traces/lte.trace, queue_limit_packets: 50}\n"));
  const Scenario scenario = load_scenario(path("story.yaml"));
  const VehicleSpec& vehicle = scenario.world.vehicles.at(0);
  ASSERT_TRUE(vehicle.to_player.trace);
  EXPECT_EQ(vehicle.to_player.trace, vehicle.to_streamer.trace);   // loaded once
  EXPECT_EQ(vehicle.to_player.trace->opportunities_per_period(), 3u);
  EXPECT_EQ(vehicle.to_player.queue_limit_packets, 50u);
}

TEST_F(ScenarioLinkTrace, PerDirection) {
  write("up.trace", "5\n");
  write("story.yaml", with_link("      to_player: {trace: up.trace}\n"));
  const Scenario scenario = load_scenario(path("story.yaml"));
  EXPECT_TRUE(scenario.world.vehicles.at(0).to_player.trace);
  EXPECT_FALSE(scenario.world.vehicles.at(0).to_streamer.trace);
}

TEST_F(ScenarioLinkTrace, ABadTraceNamesItsFileAndLine) {
  write("bad.trace", "1\n2\n1\n");
  write("story.yaml", with_link("      link: {trace: bad.trace}\n"));
  try {
    load_scenario(path("story.yaml"));
    FAIL() << "no error";
  } catch (const ScenarioError& error) {
    const std::string what = error.what();
    EXPECT_EQ(what.rfind(path("bad.trace") + ":3: timestamp 1 goes backwards", 0), 0u) << what;
    EXPECT_NE(what.find("story.yaml:6:"), std::string::npos) << what;   // where the scenario names it
  }
}

TEST_F(ScenarioLinkTrace, AMissingTraceIsAClearError) {
  write("story.yaml", with_link("      link: {trace: nowhere.trace}\n"));
  try {
    load_scenario(path("story.yaml"));
    FAIL() << "no error";
  } catch (const ScenarioError& error) {
    EXPECT_NE(std::string(error.what()).find("nowhere.trace: cannot open the delivery trace: No such file"), std::string::npos)
        << error.what();
  }
}

TEST_F(ScenarioLinkTrace, TraceAndBandwidthExcludeEachOther) {
  write("a.trace", "5\n");
  write("story.yaml", with_link("      link: {trace: a.trace, bandwidth_bps: 1000000}\n"));
  try {
    load_scenario(path("story.yaml"));
    FAIL() << "no error";
  } catch (const ScenarioError& error) {
    EXPECT_EQ(error.line(), 6);
    EXPECT_NE(error.reason().find("exclude each other"), std::string::npos) << error.what();
  }
}

TEST_F(ScenarioLinkTrace, ATunnelQueuesThenDrops) {
  // 1 ms opportunities except a 1 s gap: the loop's messages wait or are dropped, none is lost
  // to anything else, and the run still conserves messages.
  std::string text;
  for (int ms = 1; ms <= 3000; ++ms) {
    if (ms <= 500 || ms > 1500) text += std::to_string(ms) + "\n";
  }
  write("gap.trace", text);
  write("story.yaml", "seed: 1\nduration: 3s\nworld:\n  gamepad: drive\n  vehicles:\n    - name: truck-1\n"
                      "      link: {delay: 10ms, trace: gap.trace, queue_limit_packets: 20}\n"
                      "expect:\n  thresholds:\n    lost_to_player: [\"count > 0\"]\n    latency_ms: [\"max > 400\"]\n");
  const Scenario scenario = load_scenario(path("story.yaml"));
  const RunResult run = run_scenario(scenario, RunOptions{});
  const std::vector<Verdict> verdicts = evaluate(scenario, run);
  EXPECT_GT(verdicts.size(), 0u) << "no verdict: the expectations proved nothing";
  for (const Verdict& verdict : verdicts) {
    EXPECT_TRUE(verdict.passed) << verdict.title << ": expected " << verdict.expected << ", actual " << verdict.actual;
  }
}

}  // namespace
}  // namespace ocp::scenario
