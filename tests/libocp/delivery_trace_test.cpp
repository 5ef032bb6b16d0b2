// Mahimahi delivery traces: parsing (errors name file and line) and the looping timetable.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "ocp/delivery_trace.hpp"

namespace ocp {
namespace {

using namespace std::chrono_literals;

DeliveryTrace parsed(std::string_view text) {
  auto trace = DeliveryTrace::parse(text, "t.trace");
  EXPECT_TRUE(trace.ok()) << (trace.ok() ? "" : trace.error().detail);
  return std::move(trace).value();
}

std::string error_of(std::string_view text) {
  auto trace = DeliveryTrace::parse(text, "t.trace");
  EXPECT_FALSE(trace.ok());
  return trace.ok() ? "" : trace.error().detail;
}

TEST(DeliveryTrace, ParsesLinesWithRepeatsAsSeveralOpportunities) {
  const DeliveryTrace trace = parsed("5\n5\n12\n20\n");
  EXPECT_EQ(trace.opportunities_per_period(), 4u);
  EXPECT_EQ(trace.period(), 20ms);
  EXPECT_EQ(trace.time_of(0), 5ms);
  EXPECT_EQ(trace.time_of(1), 5ms);
  EXPECT_EQ(trace.time_of(2), 12ms);
  EXPECT_EQ(trace.time_of(3), 20ms);
}

TEST(DeliveryTrace, LoopsWithItsLastTimestampAsPeriod) {
  const DeliveryTrace trace = parsed("0\n10\n");
  // 0, 10 | 10, 20 | 20, 30 …: the next cycle's 0 coincides with this cycle's end.
  EXPECT_EQ(trace.time_of(2), 10ms);
  EXPECT_EQ(trace.time_of(5), 30ms);
  EXPECT_EQ(trace.time_of(2001), 10010ms);
  EXPECT_EQ(trace.first_at_or_after(0us), 0u);
  EXPECT_EQ(trace.first_at_or_after(1us), 1u);
  EXPECT_EQ(trace.first_at_or_after(10ms), 1u);   // the earlier of the two at 10 ms
  EXPECT_EQ(trace.first_at_or_after(20ms), 3u);
  EXPECT_EQ(trace.first_at_or_after(20001us), 5u);
}

TEST(DeliveryTrace, FirstAtOrAfterAgreesWithTimeOfEverywhere) {
  const DeliveryTrace trace = parsed("3\n3\n7\n7\n7\n9\n");
  for (std::int64_t at = 0; at < 40'000; at += 250) {
    const std::uint64_t index = trace.first_at_or_after(Micros{at});
    ASSERT_GE(trace.time_of(index), Micros{at}) << at;
    if (index > 0) {
      ASSERT_LT(trace.time_of(index - 1), Micros{at}) << at;
    }
  }
}

TEST(DeliveryTrace, AcceptsBlankLinesAndCarriageReturns) {
  EXPECT_EQ(parsed("1\r\n\n2\r\n").opportunities_per_period(), 2u);
}

TEST(DeliveryTrace, ParseErrorsNameFileAndLine) {
  EXPECT_EQ(error_of("1\n2\nfast\n"), "t.trace:3: expected a whole number of milliseconds, got 'fast'");
  EXPECT_EQ(error_of("1\n-4\n"), "t.trace:2: expected a whole number of milliseconds, got '-4'");
  EXPECT_EQ(error_of("1.5\n"), "t.trace:1: expected a whole number of milliseconds, got '1.5'");
  EXPECT_EQ(error_of("10\n20\n15\n"), "t.trace:3: timestamp 15 goes backwards (previous line says 20)");
  EXPECT_EQ(error_of(""), "t.trace: empty trace (no delivery opportunities)");
  EXPECT_EQ(error_of("\n \n"), "t.trace: empty trace (no delivery opportunities)");
  EXPECT_EQ(error_of("0\n0\n"), "t.trace:2: the last timestamp must be > 0 ms (it is the period the trace loops with)");
  EXPECT_NE(error_of("99999999999999999999999\n").find("t.trace:1: timestamp"), std::string::npos);
  EXPECT_NE(error_of("2000000000\n").find("is beyond"), std::string::npos);
}

}  // namespace
}  // namespace ocp
