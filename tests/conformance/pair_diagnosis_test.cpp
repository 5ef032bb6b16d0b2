// pair_diagnosis: each named cause, and none for a pair that was made up.
#include "conformance/pair_diagnosis.hpp"

#include <gtest/gtest.h>

#include <cstdint>

namespace ocp::conformance {
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

}  // namespace
}  // namespace ocp::conformance
