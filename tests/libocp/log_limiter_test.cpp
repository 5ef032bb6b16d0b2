// The log limiters (log_limiter.hpp), in virtual time: "say it once, then summarise", and a
// bounded set of names already warned about.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "captured_log.hpp"
#include "ocp/log_limiter.hpp"
#include "ocp/virtual_executor.hpp"

namespace ocp {
namespace {

SimTime limiter_ms(std::int64_t ms) { return SimTime{ms * 1000}; }

TEST(FormatSpan, SaysSecondsWithoutNoise) {
  EXPECT_EQ(format_span(Micros{5'000'000}), "5 s");
  EXPECT_EQ(format_span(Micros{250'000}), "0.25 s");
  EXPECT_EQ(format_span(Micros{1'010'000}), "1.01 s");
}

TEST(RepeatedWarning, FirstIsLoggedThenOneSummaryAPeriodThenTheEnd) {
  RepeatedWarning warning(Micros{1'000'000});
  std::vector<std::string> lines;
  std::size_t full = 0;
  // Every 10 ms for 3 s, then silence: 1 full line, then one summary a second.
  for (std::int64_t ms = 0; ms < 6000; ms += 10) {
    if (ms < 3000 && warning.occurred(limiter_ms(ms))) ++full;
    if (auto summary = warning.summary(limiter_ms(ms))) lines.push_back(summary->text("times"));
  }
  EXPECT_EQ(full, 1u);
  ASSERT_EQ(lines.size(), 3u) << ::testing::PrintToString(lines);
  EXPECT_EQ(lines[0], "100 times in the last 1 s");   // 10 … 1 000 ms
  EXPECT_EQ(lines[1], "100 times in the last 1 s");
  EXPECT_EQ(lines[2], "99 times in the last 1 s");    // 2 010 … 2 990 ms
  EXPECT_FALSE(warning.in_episode());
  EXPECT_EQ(warning.total(), 300u);
  // A new episode is logged in full again.
  EXPECT_TRUE(warning.occurred(limiter_ms(7000)));
}

TEST(RepeatedWarning, ASingleOccurrenceIsOneLineAndNoSummary) {
  RepeatedWarning warning(Micros{1'000'000});
  EXPECT_TRUE(warning.occurred(limiter_ms(0)));
  for (std::int64_t ms = 0; ms < 5000; ms += 10) EXPECT_FALSE(warning.summary(limiter_ms(ms)).has_value());
  EXPECT_FALSE(warning.in_episode());
}

TEST(RepeatedWarning, AnEpisodeShorterThanAPeriodIsSummarisedOnce) {
  RepeatedWarning warning(Micros{1'000'000});
  std::vector<RepeatedWarning::Summary> summaries;
  for (std::int64_t ms = 0; ms < 3000; ms += 10) {
    if (ms < 500) (void)warning.occurred(limiter_ms(ms));
    if (auto summary = warning.summary(limiter_ms(ms))) summaries.push_back(*summary);
  }
  ASSERT_EQ(summaries.size(), 1u);
  EXPECT_FALSE(summaries[0].episode_ended);
  EXPECT_EQ(summaries[0].text("times"), "49 times in the last 1 s");   // 10 … 490 ms, said at 1 s
  EXPECT_FALSE(warning.in_episode());   // ended at 1 490 ms, with nothing left to say
}

TEST(RepeatedWarning, WhatIsLeftWhenAnEpisodeEndsIsSaidWithinAPeriod) {
  RepeatedWarning warning(Micros{1'000'000});
  std::vector<RepeatedWarning::Summary> summaries;
  for (std::int64_t ms = 0; ms < 5000; ms += 10) {
    if (ms < 1500) (void)warning.occurred(limiter_ms(ms));
    if (auto summary = warning.summary(limiter_ms(ms))) summaries.push_back(*summary);
  }
  ASSERT_EQ(summaries.size(), 2u);
  EXPECT_EQ(summaries[0].text("times"), "100 times in the last 1 s");   // 10 … 1 000 ms
  EXPECT_FALSE(summaries[0].episode_ended);
  EXPECT_EQ(summaries[1].text("times"), "49 times in the last 1 s");   // 1 010 … 1 490, said at 2 000
  EXPECT_FALSE(warning.in_episode());
  EXPECT_TRUE(warning.occurred(limiter_ms(5000)));   // a new episode
}

// summary() called late (not every tick): the episode is over, and what it left is said.
TEST(RepeatedWarning, ALateSummaryOfAnEndedEpisodeSaysSo) {
  RepeatedWarning warning(Micros{1'000'000});
  for (std::int64_t ms = 0; ms < 500; ms += 10) (void)warning.occurred(limiter_ms(ms));
  const auto summary = warning.summary(limiter_ms(3000));
  ASSERT_TRUE(summary.has_value());
  EXPECT_TRUE(summary->episode_ended);
  EXPECT_EQ(summary->text("times"), "49 times in the last 3 s");
  EXPECT_FALSE(warning.in_episode());
}

TEST(WarnedNames, RemembersAtMostItsCapacityAndSummarisesTheRest) {
  WarnedNames names(64, Micros{5'000'000});
  std::size_t full_lines = 0;
  std::vector<RepeatedWarning::Summary> summaries;
  // 100 000 distinct names, 10 a millisecond, for 10 s; every one is repeated at once too.
  for (int k = 0; k < 100'000; ++k) {
    const SimTime now{k * 100};
    const std::string name = "ghost-" + std::to_string(k);
    if (names.first_time(name, now)) ++full_lines;
    EXPECT_FALSE(names.first_time(name, now));
    if (auto summary = names.summary(now)) summaries.push_back(*summary);
    ASSERT_LE(names.size(), 64u);
  }
  for (std::int64_t ms = 10'000; ms <= 20'000; ms += 10) {
    if (auto summary = names.summary(limiter_ms(ms))) summaries.push_back(*summary);
  }
  EXPECT_EQ(full_lines, 64u);
  EXPECT_TRUE(names.full());
  EXPECT_EQ(names.size(), 64u);
  ASSERT_EQ(summaries.size(), 2u);   // one a period: at 5 s and at 10 s
  std::uint64_t counted = 0;
  for (const auto& summary : summaries) counted += summary.count;
  EXPECT_EQ(counted, 2u * (100'000u - 64u));   // each unremembered name, twice
  // Names warned about before stay quiet; forgetting starts over.
  EXPECT_FALSE(names.first_time("ghost-0", limiter_ms(30'000)));
  names.clear();
  EXPECT_TRUE(names.first_time("ghost-0", limiter_ms(30'000)));
}

}  // namespace
}  // namespace ocp

namespace ocp {
namespace {

// A connection storm: 1 000 connections in 2 s, three lines each. Three lines a second are
// written, and the count of the rest before the next written line; a quiet connection later
// has its whole story told again.
TEST(ConnectionLogBudget, AStormWritesThreeLinesASecondAndCountsTheRest) {
  VirtualExecutor executor;
  testing::CapturedLog log;
  const Logger logger(executor, "server", log.sink());
  ConnectionLogBudget budget;   // 3 lines a second
  std::size_t written = 0;
  for (std::int64_t i = 0; i < 1000; ++i) {
    const SimTime at = SimTime{i * 2'000};
    for (int line = 0; line < 3; ++line) written += budget.admit(logger, at);
  }
  EXPECT_EQ(written, 6u);                        // 2 s of storm: 3 lines in each second
  EXPECT_EQ(budget.suppressed_total(), 2994u);
  ASSERT_EQ(log.lines().size(), 1u);             // the count, before the second second's first line
  EXPECT_NE(log.lines()[0].message.find("1497 connection lines not written in the last"), std::string::npos)
      << log.lines()[0].message;
  // A connection 10 s later: connected, closing, disconnected all written, the count first.
  for (int line = 0; line < 3; ++line) EXPECT_TRUE(budget.admit(logger, SimTime{12'000'000}));
  ASSERT_EQ(log.lines().size(), 2u);
  EXPECT_NE(log.lines()[1].message.find("1497 connection lines"), std::string::npos) << log.lines()[1].message;
}

}  // namespace
}  // namespace ocp
