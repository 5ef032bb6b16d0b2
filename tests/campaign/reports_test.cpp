// What a campaign says it checked (issue #34 item 3): a check not judged shows why, never a 0
// that reads as "passed"; each failing world shows its first violation and its replay command;
// index.html links only the files a failing world's folder got; all of it survives summary.json.
#include <gtest/gtest.h>

#include "campaign/results.hpp"

namespace ocp::campaign {
namespace {

Summary with_one_failure(bool client_worlds, std::vector<std::string> files, bool real_time = true) {
  Summary s;
  s.seed = 9;
  s.profile = "default";
  s.worlds = 2;
  s.client_worlds = client_worlds;
  s.client_real_time = client_worlds && real_time;
  WorldRecord pass;
  pass.index = 0;
  pass.hazards = {"streamer_close"};
  WorldRecord fail;
  fail.index = 1;
  fail.violation_count = 1;
  fail.violations.push_back({"conservation", 28'700'000, "v3", "to_player: message 3335 delivered but not in flight"});
  fail.files = std::move(files);
  fail.replay = "ocp_campaign run --seed 9 --worlds 2 --profile default --world 1";
  fail.hazards = {"ack_time_above_2^53", "streamer_close"};
  s.records = {pass, fail};
  return s;
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(CampaignReports, ATableSaysWhichChecksWereNotJudgedAndWhy) {
  const std::string client = summary_table(with_one_failure(true, {"world.yaml"}));
  EXPECT_TRUE(has(client, "—  fault_model               — (not judged in real time)")) << client;
  EXPECT_TRUE(has(client, "—  operator.port             — (no operator client in client worlds)")) << client;
  EXPECT_TRUE(has(client, "✓  client.echo               0")) << client;
  EXPECT_TRUE(has(client, "✗  conservation              1")) << client;
  EXPECT_TRUE(has(client, "client hazards (worlds of 2): ack_time_above_2^53 1 streamer_close 2")) << client;
  const std::string in_process = summary_table(with_one_failure(false, {"world.yaml"}));
  EXPECT_TRUE(has(in_process, "✓  fault_model               0")) << in_process;
  EXPECT_TRUE(has(in_process, "—  client.alive              — (only with --client)")) << in_process;
  EXPECT_FALSE(has(in_process, "client hazards")) << in_process;
}

// In virtual time (the default with --client) the whole oracle judges the client's worlds:
// only determinism is not, as each world runs the client once.
TEST(CampaignReports, AVirtualTimeClientCampaignJudgesTheTimingChecks) {
  const Summary virtual_time = with_one_failure(true, {"world.yaml"}, false);
  const std::string table = summary_table(virtual_time);
  EXPECT_TRUE(has(table, "✓  fault_model               0")) << table;
  EXPECT_TRUE(has(table, "✓  liveness                  0")) << table;
  EXPECT_TRUE(has(table, "✓  latency_loop              0")) << table;
  EXPECT_TRUE(has(table, "—  determinism               — (one run of the client per world)")) << table;
  EXPECT_FALSE(has(table, "not judged in real time")) << table;
  const Summary read = read_summary_json(summary_json(virtual_time), "summary.json");
  EXPECT_FALSE(read.client_real_time);
  EXPECT_EQ(summary_table(read), table);
  EXPECT_TRUE(read_summary_json(summary_json(with_one_failure(true, {"world.yaml"})), "summary.json").client_real_time);
}

TEST(CampaignReports, EachFailingWorldShowsItsFirstViolationAndReplay) {
  const std::string table = summary_table(with_one_failure(true, {"world.yaml"}));
  EXPECT_TRUE(has(table, "✗ world 1: conservation at 28700000 us on v3: to_player: message 3335 delivered but not in flight"))
      << table;
  EXPECT_TRUE(has(table, "replay: ocp_campaign run --seed 9 --worlds 2 --profile default --world 1")) << table;
  EXPECT_TRUE(has(table, "files:  failures/world-1/world.yaml")) << table;
  EXPECT_FALSE(has(table, "world 0:")) << table;
}

TEST(CampaignReports, TheIndexLinksOnlyTheFilesThatExist) {
  const std::string client = html_index(with_one_failure(true, {"world.yaml"}));
  EXPECT_TRUE(has(client, "href=\"failures/world-1/world.yaml\"")) << client;
  EXPECT_FALSE(has(client, "report.html")) << client;
  EXPECT_FALSE(has(client, "shrunk.yaml")) << client;
  const std::string shrunk = html_index(with_one_failure(false, {"world.yaml", "shrunk.yaml", "report.html"}));
  EXPECT_TRUE(has(shrunk, "href=\"failures/world-1/shrunk.yaml\"")) << shrunk;
  EXPECT_TRUE(has(shrunk, "href=\"failures/world-1/report.html\"")) << shrunk;
}

TEST(CampaignReports, FilesReplayAndHazardsSurviveSummaryJson) {
  const Summary written = with_one_failure(true, {"world.yaml"});
  const Summary read = read_summary_json(summary_json(written), "summary.json");
  EXPECT_TRUE(read.client_worlds);
  EXPECT_EQ(read.records.at(1).files, written.records.at(1).files);
  EXPECT_EQ(read.records.at(1).replay, written.records.at(1).replay);
  EXPECT_EQ(read.records.at(1).hazards, written.records.at(1).hazards);
  EXPECT_EQ(summary_table(read), summary_table(written));
  EXPECT_EQ(html_index(read), html_index(written));
}

}  // namespace
}  // namespace ocp::campaign
