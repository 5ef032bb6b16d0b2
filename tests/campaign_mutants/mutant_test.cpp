// Every invariant can fail (issue #21): with one deliberately broken core behaviour switched
// on, the oracle must report it — and with none, the same world passes.
#include <gtest/gtest.h>

#include "campaign/generator.hpp"
#include "campaign/oracle.hpp"
#include "campaign/profile.hpp"
#include "campaign/shrink.hpp"
#include "campaign/world_check.hpp"
#include "ocp/mutants.hpp"
#include "scenario/parse.hpp"

namespace ocp {
Mutant& active_mutant() {
  static Mutant mutant = Mutant::none;
  return mutant;
}
}  // namespace ocp

namespace ocp::campaign {
namespace {

struct MutantOn {
  explicit MutantOn(Mutant mutant) { active_mutant() = mutant; }
  ~MutantOn() { active_mutant() = Mutant::none; }
};

// A driving operator, and an outage long enough for NoControlMessage on the control path.
constexpr const char* outage_world = R"(
duration: 6s
world:
  gamepad: drive
  vehicles:
    - name: v1
timeline:
  - at: 1s
    outage: {direction: to_streamer, for: 2s}
expect:
  invariants: [default_controller_during_control_fault]
)";

// Pairs come back out of order: the newest valid pair must not be replaced by an older one.
constexpr const char* reorder_world = R"(
duration: 6s
world:
  gamepad: drive
  vehicles:
    - name: v1
      link: {delay: 20ms}
timeline:
  - at: 1s
    impair: {direction: to_streamer, reorder: 0.5, reorder_extra_delay: 40ms}
  - at: 4s
    impair: {direction: to_streamer, reorder: 0}
expect:
  invariants: [default_controller_during_control_fault]
)";

bool caught(const WorldOutcome& outcome, Check check) {
  for (const Violation& v : outcome.violations) {
    if (v.check == check) return true;
  }
  return false;
}

std::string describe(const WorldOutcome& outcome) {
  std::string text;
  for (const Violation& v : outcome.violations) text += std::string(check_name(v.check)) + ": " + v.detail + "\n";
  return text;
}

WorldOutcome check(const char* yaml, Mutant mutant) {
  const MutantOn on(mutant);
  return check_world(scenario::parse_scenario(yaml, "mutant.yaml"));
}

TEST(CampaignMutants, CleanWorldsPass) {
  for (const char* world : {outage_world, reorder_world}) {
    const WorldOutcome outcome = check(world, Mutant::none);
    EXPECT_EQ(outcome.violation_count, 0u) << describe(outcome);
  }
}

TEST(CampaignMutants, FaultRaisedOneTickLateIsCaught) {
  const WorldOutcome outcome = check(outage_world, Mutant::fault_raised_one_tick_late);
  ASSERT_TRUE(caught(outcome, Check::fault_model)) << describe(outcome);
  EXPECT_EQ(outcome.violations.front().fault, FaultId::NoControlMessage);
  EXPECT_TRUE(outcome.violations.front().should_be_active);
}

TEST(CampaignMutants, DefaultControllerNotAppliedIsCaught) {
  const WorldOutcome outcome = check(outage_world, Mutant::default_controller_not_applied);
  EXPECT_TRUE(caught(outcome, Check::safety_controller)) << describe(outcome);
}

TEST(CampaignMutants, StalePairAcceptedIsCaught) {
  const WorldOutcome outcome = check(reorder_world, Mutant::stale_pair_accepted);
  EXPECT_TRUE(caught(outcome, Check::latency_loop)) << describe(outcome);
}

TEST(CampaignMutants, DeliveryCountedTwiceIsCaught) {
  const WorldOutcome outcome = check(outage_world, Mutant::delivered_counted_twice);
  EXPECT_TRUE(caught(outcome, Check::conservation)) << describe(outcome);
}

}  // namespace
}  // namespace ocp::campaign

namespace ocp::campaign {
namespace {

// A known failure (a generated world with several timeline events, under a mutant) shrinks to
// at most 3 timeline events that still break the same invariant, written as a scenario that
// parses and still fails under `ocp_campaign check` (here: check_world of the parsed file).
TEST(CampaignShrink, KnownFailureShrinksToThreeEventsOrFewer) {
  const MutantOn on(Mutant::default_controller_not_applied);
  const Profile profile = load_profile(shipped_profile_path("default"));
  for (std::uint64_t index = 0; index < 40; ++index) {
    const scenario::Scenario world = generate_world(profile, 3, index);
    if (world.timeline.size() < 5 || world.duration > Micros{40'000'000}) continue;
    const WorldOutcome outcome = check_world(world);
    if (!caught(outcome, Check::safety_controller)) continue;
    const ShrinkResult shrunk = shrink(world, {Check::safety_controller, std::nullopt}, 200);
    EXPECT_LE(shrunk.scenario.timeline.size(), 3u) << "world " << index;
    EXPECT_LT(shrunk.scenario.duration, world.duration);
    const std::string yaml = regression_yaml(shrunk, "ocp_campaign check shrunk.yaml");
    const scenario::Scenario again = scenario::parse_scenario(yaml, "shrunk.yaml");
    EXPECT_TRUE(caught(check_world(again), Check::safety_controller)) << yaml;
    return;
  }
  FAIL() << "no generated world of campaign 3 fails under the mutant";
}

}  // namespace
}  // namespace ocp::campaign
