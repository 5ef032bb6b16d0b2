// A campaign's closing efficiency figures (campaign/efficiency.hpp): every figure from the
// run's own counts, CPU from the whole process (every worker thread), and the JSON report.
#include <gtest/gtest.h>

#include <rapidjson/document.h>

#include "campaign/campaign.hpp"
#include "campaign/efficiency.hpp"

namespace ocp::campaign {
namespace {

CampaignRun made_up_run() {
  CampaignRun run;
  run.workers = 4;
  run.wall_seconds = 2.0;
  run.cpu_seconds = 7.0;
  run.process_cpu_seconds = 7.5;
  run.children_cpu_seconds = 0.5;
  for (int i = 0; i < 10; ++i) {
    WorldOutcome outcome;
    outcome.duration = Micros{60'000'000};
    run.outcomes.push_back(outcome);
  }
  return run;
}

TEST(CampaignEfficiency, FiguresComeFromTheRun) {
  const Efficiency e = efficiency_of(made_up_run());
  EXPECT_EQ(e.worlds, 10u);
  EXPECT_DOUBLE_EQ(e.simulated_seconds, 600.0);
  EXPECT_DOUBLE_EQ(e.cpu_seconds(), 8.0);                  // the process and its children
  EXPECT_DOUBLE_EQ(e.simulated_per_cpu_second(), 75.0);
  EXPECT_DOUBLE_EQ(e.worlds_per_second(), 5.0);
  EXPECT_DOUBLE_EQ(e.worlds_per_second_per_worker(), 1.25);
  EXPECT_DOUBLE_EQ(e.cpu_ms_per_world(), 800.0);
  EXPECT_DOUBLE_EQ(e.world_cpu_ms_per_world(), 700.0);
  const std::string text = efficiency_text(e);
  EXPECT_NE(text.find("10 worlds on 4 workers"), std::string::npos) << text;
  EXPECT_NE(text.find("75 simulated s per CPU s"), std::string::npos) << text;
  EXPECT_NE(text.find("1.25 worlds/s per worker"), std::string::npos) << text;
}

TEST(CampaignEfficiency, JsonReportReadsBack) {
  rapidjson::Document document;
  document.Parse(efficiency_json(efficiency_of(made_up_run())).c_str());
  ASSERT_FALSE(document.HasParseError());
  EXPECT_EQ(document["workers"].GetInt(), 4);
  EXPECT_DOUBLE_EQ(document["simulated_seconds_per_cpu_second"].GetDouble(), 75.0);
  EXPECT_DOUBLE_EQ(document["worlds_per_second_per_worker"].GetDouble(), 1.25);
  EXPECT_DOUBLE_EQ(document["cpu_ms_per_world"].GetDouble(), 800.0);
}

TEST(CampaignEfficiency, NothingRunDividesByNothing) {
  const Efficiency e = efficiency_of(CampaignRun{});
  EXPECT_EQ(e.simulated_per_cpu_second(), 0.0);
  EXPECT_EQ(e.worlds_per_second(), 0.0);
  EXPECT_EQ(e.cpu_ms_per_world(), 0.0);
}

// Two worker threads: the process's CPU counts both, so it is at least what the worlds' own
// thread clocks add up to (a clock of the main thread alone would read about half).
TEST(CampaignEfficiency, ProcessCpuCountsEveryWorker) {
  CampaignOptions options;
  options.seed = 5;
  options.worlds = 6;
  options.profile = load_profile(shipped_profile_path("calm"));
  options.profile.duration = {Micros{10'000'000}, Micros{12'000'000}};
  options.jobs = 2;
  const CampaignRun run = run_campaign(options);
  ASSERT_EQ(run.outcomes.size(), 6u);
  EXPECT_EQ(run.workers, 2);
  EXPECT_GT(run.cpu_seconds, 0.0);
  EXPECT_GE(run.process_cpu_seconds, 0.95 * run.cpu_seconds);
  EXPECT_EQ(run.children_cpu_seconds, 0.0);
}

}  // namespace
}  // namespace ocp::campaign
