// The ceiling on events per simulated second (issue #36, "a ceiling on one run"): a world that
// runs away (a 1 µs control_period or ping_period, a thousand cameras at 1 000 fps) stops at
// once with exit 2 and says which ceiling and how to raise it; --max-events-per-s raises it,
// and refuses bad values with exit 2. Runs the built tool; every file in a ScratchDir.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdio>
#include <string>

#include "scenario/parse.hpp"
#include "scenario/runner.hpp"
#include "scratch_dir.hpp"

namespace ocp::scenario {
namespace {

using testing_support::ScratchDir;

struct CeilingRun {
  int exit_code = -1;
  std::string output;
  double seconds = 0;
};

CeilingRun run_ceiling_command(const std::string& command) {
  CeilingRun run;
  const auto start = std::chrono::steady_clock::now();
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return run;
  char buffer[4096];
  for (std::size_t n; (n = fread(buffer, 1, sizeof buffer, pipe)) > 0;) run.output.append(buffer, n);
  const int status = pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return run;
}

std::string ceiling_world(const std::string& vehicle_fields, const std::string& world_fields = "") {
  return "seed: 1\nduration: 10s\nworld:\n" + world_fields + "  vehicles:\n    - name: truck-1\n" + vehicle_fields +
         "expect:\n  thresholds:\n    control_gap_ms: [\"count >= 0\"]\n";
}

std::string cameras_at_1000_fps(int count) {
  std::string cameras = "      cameras:\n";
  for (int i = 0; i < count; ++i) cameras += "        - {name: cam" + std::to_string(i) + ", fps: 1000}\n";
  return cameras;
}

struct RunawayWorld {
  const char* what;
  std::string scenario;
  std::string flags;
};

void PrintTo(const RunawayWorld& runaway, std::ostream* out) { *out << runaway.what; }

class EventCeilingStopsARunaway : public ::testing::TestWithParam<RunawayWorld> {};

TEST_P(EventCeilingStopsARunaway, WithExitCode2AtOnce) {
  ScratchDir scratch("ocp_event_ceiling");
  const std::string file = scratch.write("runaway.yaml", GetParam().scenario).string();
  const CeilingRun run = run_ceiling_command(std::string(OCP_SCENARIO_PATH) + " run " + file + " --no-trace --out " +
                                  (scratch / "out").string() + " " + GetParam().flags);
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("events in the simulated second from 0s: over the ceiling of events per simulated second"),
            std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("--max-events-per-s raises it"), std::string::npos) << run.output;
  EXPECT_LT(run.seconds, 60.0) << "stopped within the first simulated second, not after the run";
}

INSTANTIATE_TEST_SUITE_P(
    Table, EventCeilingStopsARunaway,
    ::testing::Values(RunawayWorld{"control_period_1us", ceiling_world("      control_period: 1us\n"), ""},
                      RunawayWorld{"ping_period_1us", ceiling_world("", "  player: {ping_period: 1us}\n"), ""},
                      RunawayWorld{"a_thousand_cameras_at_1000_fps", ceiling_world(cameras_at_1000_fps(1000)), ""},
                      RunawayWorld{"two_cameras_at_1000_fps_under_a_ceiling_of_1000", ceiling_world(cameras_at_1000_fps(2)),
                                   "--max-events-per-s 1000"}),
    [](const auto& info) { return std::string(info.param.what); });

TEST(EventCeiling, TheFlagRaisesIt) {
  ScratchDir scratch("ocp_event_ceiling");
  const std::string file = scratch.write("busy.yaml", ceiling_world("      control_period: 100us\n")).string();
  const std::string base = std::string(OCP_SCENARIO_PATH) + " run " + file + " --no-trace --out " + (scratch / "out").string();
  const CeilingRun refused = run_ceiling_command(base + " --max-events-per-s 10000");
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  const CeilingRun raised = run_ceiling_command(base + " --max-events-per-s 100000000");
  EXPECT_EQ(raised.exit_code, 0) << raised.output;
}

// 16 vehicles (a campaign profile's most) with four cameras at 1 000 fps each: under the default.
TEST(EventCeiling, TheDefaultLetsTheBusiestCampaignFleetRun) {
  ScratchDir scratch("ocp_event_ceiling");
  std::string fleet = "seed: 1\nduration: 3s\nworld:\n  fleet: true\n  vehicles:\n";
  for (int v = 0; v < 16; ++v) fleet += "    - name: v" + std::to_string(v) + "\n" + cameras_at_1000_fps(4);
  fleet += "expect:\n  thresholds:\n    control_gap_ms: [\"count > 0\"]\n";
  const std::string file = scratch.write("fleet.yaml", fleet).string();
  const CeilingRun run = run_ceiling_command(std::string(OCP_SCENARIO_PATH) + " run " + file + " --no-trace --out " + (scratch / "out").string());
  EXPECT_EQ(run.exit_code, 0) << run.output;
}

struct BadCeilingValue {
  const char* what;
  const char* value;
};

class EventCeilingFlagRefuses : public ::testing::TestWithParam<BadCeilingValue> {};

// ocp_campaign's run and check take the same option: tests/campaign/cli_test.cpp.
TEST_P(EventCeilingFlagRefuses, WithExitCode2) {
  ScratchDir scratch("ocp_event_ceiling");
  const std::string file = scratch.write("ok.yaml", ceiling_world("")).string();
  const CeilingRun run = run_ceiling_command(std::string(OCP_SCENARIO_PATH) + " run " + file + " --list --max-events-per-s '" +
                                  GetParam().value + "'");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("--max-events-per-s"), std::string::npos) << run.output;
}

INSTANTIATE_TEST_SUITE_P(Table, EventCeilingFlagRefuses,
                         ::testing::Values(BadCeilingValue{"zero", "0"}, BadCeilingValue{"negative", "-1"},
                                           BadCeilingValue{"nan", "nan"}, BadCeilingValue{"infinity", "inf"},
                                           BadCeilingValue{"fraction", "1500.5"}, BadCeilingValue{"empty", ""},
                                           BadCeilingValue{"words", "many"}, BadCeilingValue{"below_the_floor", "999"},
                                           BadCeilingValue{"overflow", "18446744073709551616"},
                                           BadCeilingValue{"past_the_top", "1e30"}),
                         [](const auto& info) { return std::string(info.param.what); });

// The library call says the same: a HarnessError, which the tools turn into exit 2.
TEST(EventCeiling, RunScenarioThrowsAHarnessErrorNamingTheCeiling) {
  const Scenario scenario = parse_scenario(ceiling_world("      control_period: 1us\n"), "runaway.yaml");
  RunOptions options;
  options.trace = false;
  try {
    run_scenario(scenario, options);
    ADD_FAILURE() << "the runaway ran";
  } catch (const HarnessError& error) {
    EXPECT_NE(std::string(error.what()).find("more than 1000000 events in the simulated second from 0s"), std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace ocp::scenario
