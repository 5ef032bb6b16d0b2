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

}  // namespace
}  // namespace ocp::scenario
