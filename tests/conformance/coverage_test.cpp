// The coverage table's parser (conformance/coverage.hpp), the requirement table and its checker
// (conformance/requirements.hpp) and the standing rules' helpers (conformance/standing_rules.hpp):
// pure functions, no client.
#include <gtest/gtest.h>

#include "conformance/coverage.hpp"
#include "conformance/requirements.hpp"
#include "conformance/vehicle_cases.hpp"
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

// The checker behind ConformanceCoverage.EveryRequirementHasACaseAndABrokenClient, on a
// made-up table: each way a table can fall short is reported.
Requirement requirement_sample(const std::string& id, Tier tier, std::vector<std::string> cases, std::vector<std::string> broken_by,
                               std::string not_covered = "") {
  return {id, "a rule", "SPEC §2", tier, std::move(cases), std::move(broken_by), std::move(not_covered)};
}

bool mentions(const std::vector<std::string>& problems, const std::string& text) {
  for (const auto& p : problems) {
    if (p.find(text) != std::string::npos) return true;
  }
  return false;
}

TEST(Requirements, CheckerPassesACompleteTable) {
  const std::vector<CaseInfo> cases{coverage_sample("v/1/1", Tier::must, "broken_client.py a (or b)"),
                                    coverage_sample("v/1/2", Tier::info, "never fails (INFO)")};
  const auto problems = requirement_problems({requirement_sample("V-1", Tier::must, {"v/1/1"}, {"broken_client.py b"}),
                                              requirement_sample("V-2", Tier::should, {}, {}, "not on the wire")},
                                             cases);
  EXPECT_TRUE(problems.empty()) << problems.front();
}

TEST(Requirements, CheckerFailsEveryGap) {
  const std::vector<CaseInfo> cases{coverage_sample("v/1/1", Tier::must, "broken_client.py a"),
                                    coverage_sample("v/1/2", Tier::should, "broken_client.py c"),
                                    coverage_sample("v/1/3", Tier::must, "nobody yet")};
  const auto problems = requirement_problems({requirement_sample("V-must-no-case", Tier::must, {}, {}, "too hard"),
                                              requirement_sample("V-no-reason", Tier::should, {}, {}),
                                              requirement_sample("V-no-client", Tier::must, {"v/1/1"}, {}),
                                              requirement_sample("V-wrong-client", Tier::must, {"v/1/1"}, {"broken_client.py c"}),
                                              requirement_sample("V-ghost", Tier::must, {"v/9/9"}, {"broken_client.py a"}),
                                              requirement_sample("V-no-client", Tier::should, {"v/1/1"}, {"broken_client.py a"})},
                                             cases);
  EXPECT_TRUE(mentions(problems, "V-must-no-case (MUST) has no case"));
  EXPECT_TRUE(mentions(problems, "V-no-reason has no case and does not say why"));
  EXPECT_TRUE(mentions(problems, "V-no-client names no broken client"));
  EXPECT_TRUE(mentions(problems, "V-wrong-client: `broken_client.py c` is not a broken client of its cases"));
  EXPECT_TRUE(mentions(problems, "V-ghost names case v/9/9, which does not exist"));
  EXPECT_TRUE(mentions(problems, "V-no-client is listed twice"));
  EXPECT_TRUE(mentions(problems, "case v/1/2 covers no requirement"));
  EXPECT_FALSE(mentions(problems, "case v/1/1 covers no requirement"));
  // Also: V-ghost's client is no run of its (missing) case, and v/1/3 covers no requirement.
  EXPECT_EQ(problems.size(), 9u);
}

TEST(Requirements, TableShowsCasesVerdictsAndWhyARowIsNotCovered) {
  const std::vector<CaseInfo> cases{coverage_sample("v/1/1", Tier::must, "broken_client.py a (with v/1/2)")};
  const std::string table = requirement_table({requirement_sample("V-1", Tier::must, {"v/1/1"}, {"broken_client.py a"}),
                                               requirement_sample("V-2", Tier::should, {}, {}, "not on the wire")},
                                              cases);
  EXPECT_NE(table.find("| `V-1` | a rule | SPEC §2 | MUST | `v/1/1` | `broken_client.py a` (FAILED on `v/1/1`, with v/1/2) |"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("| `V-2` | a rule | SPEC §2 | SHOULD | — | not covered: not on the wire |"), std::string::npos) << table;
}

// The real tables: every MUST requirement has a case, every covered one a broken client its
// cases name (so CoverageBrokenClient.GetsItsVerdict runs it), every case covers one.
std::vector<CaseInfo> requirement_case_infos(const std::vector<VehicleCase>& cases) {
  std::vector<CaseInfo> infos;
  for (const auto& c : cases) infos.push_back(c.body.info);
  return infos;
}

TEST(Requirements, EveryRequirementHasACaseAndABrokenClient) {
  for (const auto& problem : requirement_problems(vehicle_requirements(), requirement_case_infos(vehicle_cases()))) ADD_FAILURE() << problem;
  for (const auto& problem : requirement_problems(operator_requirements(), requirement_case_infos(operator_cases()))) ADD_FAILURE() << problem;
  EXPECT_GE(vehicle_requirements().size() + operator_requirements().size(), 50u);
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
