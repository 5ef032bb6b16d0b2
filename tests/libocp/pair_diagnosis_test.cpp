// pair_diagnosis: each named cause, and none for a pair that was made up; the Streamer's
// judgement of one rejected pair and its hint.
#include "ocp/pair_diagnosis.hpp"

#include <gtest/gtest.h>

#include <cstdint>

namespace ocp {
namespace {

constexpr std::uint64_t two_to_53 = std::uint64_t{1} << 53;
constexpr std::uint64_t near_2_to_62 = (std::uint64_t{1} << 62) + 12345;

struct Row {
  const char* name;
  AckPair altered;
  const char* cause_starts;   // "" = no named cause
};

class PairDiagnosisTable : public ::testing::TestWithParam<Row> {};

TEST_P(PairDiagnosisTable, NamesTheCause) {
  const std::vector<AckPair> sent{{two_to_53 + 1, 0x80000001u}, {near_2_to_62, 7u}, {1000, 42u}};
  const PairDiagnosis diagnosis = diagnose_altered_pairs({GetParam().altered}, sent);
  const std::string expected = GetParam().cause_starts;
  if (expected.empty()) {
    EXPECT_EQ(diagnosis.cause, "") << diagnosis.example;
  } else {
    EXPECT_EQ(diagnosis.cause.rfind(expected, 0), 0u) << diagnosis.cause;
    EXPECT_FALSE(diagnosis.example.empty());
  }
}

INSTANTIATE_TEST_SUITE_P(
    Causes, PairDiagnosisTable,
    ::testing::Values(Row{"odd_above_2_53_rounded_to_even", {two_to_53, 0x80000001u}, "ack_time rounded through a double"},
                      // 2^62 + 12345 is 2^62 + 12288 as a double (doubles are 1024 apart there).
                      Row{"near_2_62_rounded", {(std::uint64_t{1} << 62) + 12288, 7u}, "ack_time rounded through a double"},
                      Row{"small_values_never_round", {1001, 42u}, ""},
                      Row{"partial_echo", {1000, 7u}, "a partial echo"},
                      Row{"mac_altered", {1000, 43u}, "ack_time_mac altered"},
                      Row{"made_up", {0, 0u}, ""},
                      Row{"far_off_with_a_sent_mac", {near_2_to_62 + 5000, 7u}, ""}),
    [](const ::testing::TestParamInfo<Row>& info) { return std::string(info.param.name); });


struct JudgeRow {
  const char* name;
  AckPair altered;
  PairCause cause;
  AckPair nearest;
  const char* hint_has;
};

class PairJudgementTable : public ::testing::TestWithParam<JudgeRow> {};

TEST_P(PairJudgementTable, NamesTheCauseAndTheNearestIssuedPair) {
  const std::vector<AckPair> issued{{two_to_53 + 1, 0x80000001u}, {two_to_53 + 10'001, 9u}, {1000, 42u}, {2000, 43u}};
  const JudgeRow& row = GetParam();
  const PairJudgement judgement = judge_altered_pair(row.altered, issued);
  EXPECT_EQ(pair_cause_name(judgement.cause), pair_cause_name(row.cause));
  ASSERT_TRUE(judgement.nearest_issued.has_value());
  EXPECT_EQ(judgement.nearest_issued->ack_time, row.nearest.ack_time);
  EXPECT_EQ(judgement.nearest_issued->ack_time_mac, row.nearest.ack_time_mac);
  const std::string hint = describe_rejected_pair(row.altered, judgement);
  EXPECT_NE(hint.find(row.hint_has), std::string::npos) << hint;
  // The hint names the issued pair it compares with.
  EXPECT_NE(hint.find(std::to_string(row.nearest.ack_time)), std::string::npos) << hint;
}

INSTANTIATE_TEST_SUITE_P(
    Causes, PairJudgementTable,
    ::testing::Values(
        JudgeRow{"off_by_one_above_2_53", {two_to_53, 0x80000001u}, PairCause::rounded_through_double,
                 {two_to_53 + 1, 0x80000001u}, "ack_time differs by 1 from issued pair"},
        JudgeRow{"partial_echo", {1000, 43u}, PairCause::partial_echo, {1000, 42u}, "partial echo"},
        JudgeRow{"mac_altered", {2000, 7u}, PairCause::mac_altered, {2000, 43u}, "MAC altered"},
        JudgeRow{"small_ack_time_altered", {1001, 42u}, PairCause::ack_time_altered, {1000, 42u},
                 "differs by 1 from issued pair"},
        JudgeRow{"neither_field_issued", {1900, 5u}, PairCause::not_issued, {2000, 43u}, "stale pair"}),
    [](const ::testing::TestParamInfo<JudgeRow>& info) { return std::string(info.param.name); });

TEST(PairJudgement, NothingIssuedYetSaysSo) {
  const PairJudgement judgement = judge_altered_pair({5, 6u}, {});
  EXPECT_FALSE(judgement.nearest_issued);
  EXPECT_NE(describe_rejected_pair({5, 6u}, judgement).find("no pair was issued"), std::string::npos);
}

}  // namespace
}  // namespace ocp
