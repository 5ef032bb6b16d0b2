// Campaign runs, shards, merge and the outputs (issue #21): the same seed gives the same
// verdicts; merge(shards) writes exactly what one run writes; merge refuses another campaign.
#include <gtest/gtest.h>

#include "campaign/campaign.hpp"
#include "campaign/results.hpp"

namespace ocp::campaign {
namespace {

CampaignOptions small_campaign(std::uint64_t seed, Shard shard = {}) {
  CampaignOptions options;
  options.seed = seed;
  options.worlds = 12;
  options.profile = load_profile(shipped_profile_path("calm"));
  options.profile.duration = {Micros{10'000'000}, Micros{12'000'000}};
  options.jobs = 2;
  options.shard = shard;
  return options;
}

TEST(Campaign, SameSeedSameVerdicts) {
  const CampaignOptions options = small_campaign(11);
  const std::string first = summary_json(summarise(options, run_campaign(options)));
  const std::string second = summary_json(summarise(options, run_campaign(options)));
  EXPECT_EQ(first, second);
  EXPECT_NE(first.find("\"worlds_run\": 12"), std::string::npos);
}

TEST(Campaign, MergedShardsEqualOneRun) {
  const CampaignOptions whole = small_campaign(21);
  const Summary local = summarise(whole, run_campaign(whole));
  std::vector<Summary> shards;
  for (std::uint32_t i = 0; i < 3; ++i) {
    const CampaignOptions part = small_campaign(21, {i, 3});
    // Through the file format, as `ocp_campaign merge` reads shards.
    shards.push_back(read_summary_json(summary_json(summarise(part, run_campaign(part))), "shard.json"));
  }
  std::swap(shards[0], shards[2]);   // any order
  const Summary merged = merge_summaries(shards);
  EXPECT_EQ(summary_json(merged), summary_json(local));
  EXPECT_EQ(junit_xml(merged), junit_xml(local));
  EXPECT_EQ(html_index(merged), html_index(local));
}

TEST(Campaign, MergeRefusesAnotherCampaignsShards) {
  const CampaignOptions a = small_campaign(31, {0, 2});
  CampaignOptions b = small_campaign(32, {1, 2});
  b.worlds = 2;
  Summary first = summarise(a, CampaignRun{});
  Summary other_seed = summarise(b, CampaignRun{});
  EXPECT_THROW(merge_summaries({first, other_seed}), MergeError);
  Summary other_profile = summarise(small_campaign(31, {1, 2}), CampaignRun{});
  other_profile.profile_digest ^= 1;
  EXPECT_THROW(merge_summaries({first, other_profile}), MergeError);
  EXPECT_THROW(merge_summaries({first, first}), MergeError);   // the same shard twice
}

TEST(Campaign, ShardsSplitTheWorlds) {
  const Shard shard{1, 4};
  EXPECT_TRUE(shard.contains(1));
  EXPECT_TRUE(shard.contains(5));
  EXPECT_FALSE(shard.contains(4));
}

TEST(Campaign, StopKeepsFinishedWorlds) {
  CampaignOptions options = small_campaign(41);
  std::atomic<bool> stop{false};
  options.stop = [&stop] { return stop.load(); };
  options.jobs = 1;
  const CampaignRun run = run_campaign(options, [&](const Progress& progress) {
    if (progress.done == 3) stop.store(true);
  });
  EXPECT_TRUE(run.interrupted);
  EXPECT_EQ(run.outcomes.size(), 3u);
}

}  // namespace
}  // namespace ocp::campaign
