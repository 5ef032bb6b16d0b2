// Same file + seed → byte-identical trace.jsonl; another seed → another trace where the
// scenario draws random numbers (jitter, loss).
#include "scenario_test_support.hpp"

namespace ocp::scenario {
namespace {

const std::string jittery = R"(seed: 42
duration: 3s
world:
  gamepad: drive
  vehicles:
    - name: truck-1
      link: {delay: 20ms, jitter: 8ms, loss: 0.05, duplicate: 0.01, reorder: 0.01, reorder_extra_delay: 5ms}
timeline:
  - {at: 1s, impair: {delay: 80ms}, ramp: 1s}
  - {at: 2s, disconnect: {}}
expect:
  thresholds:
    latency_ms: ["count > 0"]
)";

TEST(ScenarioDeterminism, SameSeedSameTraceByteForByte) {
  RunOptions options;
  options.trace_payloads = true;
  const auto first = test::run_text(jittery, options);
  const auto second = test::run_text(jittery, options);
  ASSERT_GT(first.run.trace_jsonl.size(), 100'000u);
  EXPECT_TRUE(first.run.trace_jsonl == second.run.trace_jsonl) << "reproduce with seed " << first.run.seed;
  EXPECT_EQ(first.run.trace_digest, second.run.trace_digest);
}

TEST(ScenarioDeterminism, OtherSeedOtherTrace) {
  RunOptions options;
  const auto first = test::run_text(jittery, options);
  options.seed = 43;
  const auto other = test::run_text(jittery, options);
  EXPECT_EQ(other.run.seed, 43u);
  EXPECT_NE(first.run.trace_digest, other.run.trace_digest);
}

// The trace and the Observer's choice of buses must not change what is observed: the same
// faults, series and message counts with and without trace.jsonl.
TEST(ScenarioDeterminism, TraceDoesNotChangeTheVerdicts) {
  RunOptions with_trace, without_trace;
  without_trace.trace = false;
  const auto traced = test::run_text(jittery, with_trace);
  const auto bare = test::run_text(jittery, without_trace);
  EXPECT_EQ(traced.run.observations.faults, bare.run.observations.faults);
  const auto& a = traced.run.observations.vehicles.at("truck-1");
  const auto& b = bare.run.observations.vehicles.at("truck-1");
  EXPECT_EQ(a.latency_ms.points(), b.latency_ms.points());
  EXPECT_EQ(a.latency_ms.count(), b.latency_ms.count());
  EXPECT_EQ(a.to_streamer.dropped, b.to_streamer.dropped);
  EXPECT_EQ(a.to_player.sent, b.to_player.sent);
  EXPECT_EQ(traced.verdicts.front().actual, bare.verdicts.front().actual);
}

}  // namespace
}  // namespace ocp::scenario
