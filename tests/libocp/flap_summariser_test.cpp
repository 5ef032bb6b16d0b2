// The flapping-fault log limiter (flap_summariser.hpp), in virtual time: exact edges are
// logged until the condition flaps; then one summary, quiet while the pattern holds, and one
// line when it stops.
#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

#include "ocp/flap_summariser.hpp"

namespace ocp {
namespace {

SimTime at_ms(std::int64_t ms) { return SimTime{ms * 1000}; }

struct Log {
  std::vector<std::string> lines;
  std::size_t edges = 0;
};

// Raised for `on_ms`, cleared for `off_ms`, repeatedly from `from_ms` to `to_ms`, with the
// condition evaluated every 10 ms in between (as the Streamer's control tick does).
void flap(FlapSummariser& flaps, Log& log, std::int64_t from_ms, std::int64_t to_ms, std::int64_t on_ms,
          std::int64_t off_ms) {
  bool active = false;
  std::int64_t next_edge = from_ms;
  for (std::int64_t ms = from_ms; ms < to_ms; ms += 10) {
    if (ms >= next_edge) {
      active = !active;
      next_edge = ms + (active ? on_ms : off_ms);
      const auto verdict = flaps.on_edge(active, at_ms(ms));
      if (verdict.log_edge) ++log.edges;
      if (verdict.summary) log.lines.push_back(*verdict.summary);
    } else if (auto line = flaps.on_steady(at_ms(ms))) {
      log.lines.push_back(*line);
    }
  }
}

TEST(FlapSummariser, RareEdgesAreLoggedOneByOne) {
  FlapSummariser flaps("HighLatency");
  Log log;
  flap(flaps, log, 0, 20'000, 2000, 3000);  // 4 raises in 20 s: never 4 within 5 s
  EXPECT_EQ(log.edges, 8u);
  EXPECT_TRUE(log.lines.empty());
  EXPECT_FALSE(flaps.flapping());
}

TEST(FlapSummariser, FlappingIsSummarisedOnceThenQuietThenEnds) {
  FlapSummariser flaps("HighLatency");
  Log log;
  // 60 ms on, 40 ms off: 10 raises a second, active 60 % of the time, for 5 s.
  flap(flaps, log, 0, 5000, 60, 40);
  EXPECT_EQ(log.edges, 6u);  // raises 1-3 and their clears, before the 4th raise
  ASSERT_EQ(log.lines.size(), 1u) << ::testing::PrintToString(log.lines);
  EXPECT_EQ(log.lines[0], "HighLatency flapping: raised 4× in the last 0.3 s, active 60 % of the time");
  EXPECT_TRUE(flaps.flapping());
  // Then steady (cleared) for a whole window: one line, and edges are logged again.
  for (std::int64_t ms = 5000; ms <= 10'000; ms += 10) {
    if (auto line = flaps.on_steady(at_ms(ms))) log.lines.push_back(*line);
  }
  ASSERT_EQ(log.lines.size(), 2u) << ::testing::PrintToString(log.lines);
  EXPECT_EQ(log.lines[1], "HighLatency stopped flapping: cleared now; raised 50× while flapping");
  EXPECT_FALSE(flaps.flapping());
  EXPECT_TRUE(flaps.on_edge(true, at_ms(11'000)).log_edge);
}

TEST(FlapSummariser, ANewPatternIsSummarisedAgain) {
  FlapSummariser flaps("HighLatency");
  Log log;
  flap(flaps, log, 0, 10'000, 60, 40);      // 10 raises/s
  ASSERT_EQ(log.lines.size(), 1u) << ::testing::PrintToString(log.lines);
  flap(flaps, log, 10'000, 20'000, 900, 100);  // 1 raise/s, active 90 %
  ASSERT_EQ(log.lines.size(), 2u) << ::testing::PrintToString(log.lines);
  EXPECT_EQ(log.lines[1], "HighLatency flapping: raised 5× in the last 5 s, active 90 % of the time");
}

}  // namespace
}  // namespace ocp

namespace ocp {
namespace {

// Issue #19 item 8: "VehicleNoResponse flapping: raised 1× in the last 5 s, active 0 %" — after
// a pause in which nobody called on_steady (the process was stopped), the next edge found one
// raise in the window and still called it flapping. A single raise is never flapping.
TEST(FlapSummariser, AnEdgeAfterALongPauseEndsTheFlappingInsteadOfCallingOneRaiseFlapping) {
  FlapSummariser flaps("VehicleNoResponse");
  Log log;
  flap(flaps, log, 0, 5000, 60, 40);
  ASSERT_TRUE(flaps.flapping());
  const auto verdict = flaps.on_edge(true, at_ms(20'000));   // nothing in between
  EXPECT_TRUE(verdict.log_edge);
  ASSERT_TRUE(verdict.summary.has_value());
  EXPECT_EQ(*verdict.summary, "VehicleNoResponse stopped flapping: active now; raised 50× while flapping");
  EXPECT_FALSE(flaps.flapping());
  EXPECT_TRUE(flaps.on_edge(false, at_ms(20'010)).log_edge);
}

TEST(FlapSummariser, AShareThatIsNeitherNoneNorAllIsNotRoundedToIt) {
  FlapSummariser flaps("HighLatency");
  std::optional<std::string> summary;
  for (std::int64_t ms = 0; ms <= 3000; ms += 1000) {   // 4 raises of 1 ms each in 3 s
    summary = flaps.on_edge(true, at_ms(ms)).summary;
    if (!summary) {
      EXPECT_FALSE(flaps.on_edge(false, at_ms(ms + 1)).summary.has_value());
    }
  }
  ASSERT_TRUE(summary.has_value());
  EXPECT_EQ(*summary, "HighLatency flapping: raised 4× in the last 3 s, active <1 % of the time");

  FlapSummariser mostly_on("HighLatency");
  for (std::int64_t ms = 0; ms <= 3000; ms += 1000) {   // cleared for 1 ms a second
    summary = mostly_on.on_edge(true, at_ms(ms)).summary;
    if (!summary) (void)mostly_on.on_edge(false, at_ms(ms + 999));
  }
  ASSERT_TRUE(summary.has_value());
  EXPECT_EQ(*summary, "HighLatency flapping: raised 4× in the last 3 s, active >99 % of the time");
}

}  // namespace
}  // namespace ocp
