// The coverage table's parser (conformance/coverage.hpp) and the standing rules' helpers
// (conformance/standing_rules.hpp): pure functions, no client.
#include <gtest/gtest.h>

#include "conformance/coverage.hpp"
#include "conformance/standing_rules.hpp"

namespace ocp::conformance {
namespace {

CaseInfo coverage_sample(const std::string& id, Tier tier, const std::string& broken_by) {
  CaseInfo info;
  info.id = id;
  info.title = "a rule";
  info.source = "SPEC §2";
  info.tier = tier;
  info.broken_by = broken_by;
  return info;
}

TEST(Coverage, BrokenClientsAreParsedWithAlternativesVerdictsAndCompanionCases) {
  const auto runs = broken_client_runs(coverage_sample(
      "vehicle/9/1", Tier::must,
      "vehicle_client --misbehave-x (or --misbehave-y); broken_client.py a (or b, vehicle_client --misbehave-z); "
      "broken_client.py c (NON-STRICT); broken_client.py d (FAILED; it also does e); broken_client.py f (with vehicle/9/2); "
      "broken_client.py g (g-ok passes)"));
  std::vector<std::string> clients, verdicts;
  for (const auto& r : runs) {
    clients.push_back(r.client);
    verdicts.push_back(r.verdict);
  }
  EXPECT_EQ(clients, (std::vector<std::string>{"vehicle_client --misbehave-x", "vehicle_client --misbehave-y", "broken_client.py a",
                                               "broken_client.py b", "vehicle_client --misbehave-z", "broken_client.py c",
                                               "broken_client.py d", "broken_client.py f", "broken_client.py g"}));
  EXPECT_EQ(verdicts[5], "NON-STRICT");
  EXPECT_EQ(verdicts[6], "FAILED");
  EXPECT_EQ(runs[7].cases, "vehicle/9/1,vehicle/9/2");
  EXPECT_EQ(runs[0].cases, "vehicle/9/1");
}

TEST(Coverage, ShouldCasesExpectNonStrictAndInfoCasesNameNoClient) {
  EXPECT_EQ(broken_client_runs(coverage_sample("v/1/1", Tier::should, "broken_client.py a")).front().verdict, "NON-STRICT");
  EXPECT_TRUE(broken_client_runs(coverage_sample("v/1/2", Tier::info, "never fails (INFO)")).empty());
}

TEST(Coverage, TableMarksAMustCaseWithoutABrokenClient) {
  const std::string table = coverage_table({coverage_sample("v/1/1", Tier::must, "nobody yet"),
                                            coverage_sample("v/1/2", Tier::must, "broken_client.py a")});
  EXPECT_NE(table.find("| a rule | SPEC §2 | MUST | `v/1/1` | **none** |"), std::string::npos) << table;
  EXPECT_NE(table.find("`broken_client.py a` (FAILED)"), std::string::npos) << table;
}

WireLogEntry standing_sample(std::int64_t time_us, std::string text, bool drained = false) {
  WireLogEntry entry;
  entry.time_us = time_us;
  entry.kind = WireEntryKind::in;
  entry.text = std::move(text);
  entry.drained = drained;
  return entry;
}

std::optional<StandingFinding> standing_sample_rule(const WireLogEntry& entry) {
  if (entry.drained) return StandingFinding{Verdict::failed, "oversized"};
  if (entry.text == "odd") return StandingFinding{Verdict::non_strict, "odd"};
  return std::nullopt;
}

TEST(StandingRules, TheFirstFailingFrameIsFoundAndNamedInTheRulesCase) {
  const std::vector<WireLogEntry> log{standing_sample(1000, "fine"), standing_sample(2000, "odd"),
                                      standing_sample(3000, "", true), standing_sample(4000, "", true)};
  const auto hit = first_standing_violation(standing_sample_rule, log, 3, "vehicle/3.3/1");
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->time_us, 3000);   // a failure outranks the earlier NON-STRICT frame
  EXPECT_EQ(hit->finding.verdict, Verdict::failed);
  CaseResult result;
  result.info.id = "vehicle/2/1";
  result.verdict = Verdict::ok;
  result.actual = "100 responses";
  apply_standing_hit(result, *hit);
  EXPECT_EQ(result.verdict, Verdict::failed);
  EXPECT_NE(result.actual.find("oversized in case vehicle/3.3/1 at 3.0 ms"), std::string::npos) << result.actual;
}

StandingHit standing_hit_sample(std::size_t case_index, std::string case_id, Verdict verdict) {
  StandingHit hit;
  hit.case_index = case_index;
  hit.case_id = std::move(case_id);
  hit.finding.verdict = verdict;
  hit.finding.problem = verdict == Verdict::failed ? "bad" : "odd";
  return hit;
}

TEST(StandingRules, TheWorseAndThenTheEarlierCaseIsKeptAndNothingIsDowngraded) {
  std::optional<StandingHit> kept;
  keep_first_hit(kept, standing_hit_sample(5, "b", Verdict::non_strict));
  keep_first_hit(kept, standing_hit_sample(7, "c", Verdict::failed));
  keep_first_hit(kept, standing_hit_sample(2, "a", Verdict::failed));
  keep_first_hit(kept, standing_hit_sample(1, "z", Verdict::non_strict));
  ASSERT_TRUE(kept.has_value());
  EXPECT_EQ(kept->case_id, "a");
  CaseResult failed;
  failed.verdict = Verdict::failed;
  failed.actual = "own failure";
  apply_standing_hit(failed, standing_hit_sample(1, "z", Verdict::non_strict));
  EXPECT_EQ(failed.verdict, Verdict::failed);
  EXPECT_EQ(failed.actual, "own failure");
}

}  // namespace
}  // namespace ocp::conformance
