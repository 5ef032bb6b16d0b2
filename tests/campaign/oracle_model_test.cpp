// The oracle's model of the world against what the cores document (issue #21), for findings of
// the 10 000-world benchmark campaign that were the oracle's mistake, not the simulator's.
#include <gtest/gtest.h>

#include "campaign/world_check.hpp"
#include "campaign/world_facts.hpp"
#include "scenario/parse.hpp"

namespace ocp::campaign {
namespace {

// Campaign 1 of bench-1v60s, world 426, shrunk: a frame-loop stall injected while another blocks
// the loop runs after it (frame_loop.hpp), so StreamerSlow stays up past the first one's end.
const char* const queued_stalls_world = R"(seed: 7
duration: 18100ms
world:
  gamepad: drive
  vehicles:
    - name: v1
      streamer_slow_threshold: 474ms
      cameras: [{name: cam1, fps: 47}]
timeline:
  - {at: 16051ms, frame_loop_stall: {vehicle: v1, for: 1318ms}}
  - {at: 16086ms, frame_loop_stall: {vehicle: v1, for: 1442ms}}
expect:
  invariants: [default_controller_during_control_fault]
)";

TEST(OracleModel, AFrameLoopStallInjectedDuringAnotherQueuesBehindIt) {
  const scenario::Scenario world = scenario::parse_scenario(queued_stalls_world, "queued_stalls.yaml");
  const std::vector<Window> stalls = frame_loop_stalls(world, "v1");
  ASSERT_EQ(stalls.size(), 2u);
  EXPECT_EQ(stalls[1].start, stalls[0].end);
  EXPECT_EQ(stalls[1].end, SimTime{16'051'000 + 1'318'000 + 1'442'000});
  EXPECT_GE(quiet_point(world), stalls[1].end);
  const WorldOutcome outcome = check_world(world);
  EXPECT_EQ(outcome.violation_count, 0u) << (outcome.violations.empty() ? "" : outcome.violations.front().detail);
}

}  // namespace
}  // namespace ocp::campaign
