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
#include "scenario/runner.hpp"
#include "scenario/verdicts.hpp"

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

// An operator client on the Player's :4001: its fault lists change (an unplug), and it sends a
// malformed frame once (at the 4.5 s keep-alive), is closed and comes back.
constexpr const char* operator_world = R"(
duration: 8s
world:
  gamepad: drive
  operator_client: {connect: true, keep_alive_period: 500ms, reconnect_backoff: 200ms}
  vehicles:
    - name: v1
timeline:
  - {at: 2s, gamepad: unplug}
  - {at: 3s, gamepad: replug}
  - {at: 4100ms, operator_misbehave: {malformed_json: true}}
  - {at: 4700ms, operator_misbehave: {}}
expect:
  invariants: [default_controller_during_control_fault]
)";

// The operator client returns the SEI pair (client data, source tcp, through its connection):
// tcp is the locked source. At 3 s it hangs up inside a frame and is back 1 s later.
constexpr const char* locked_client_world = R"(
duration: 6s
world:
  gamepad: drive
  operator_client: {connect: true, keep_alive_period: 100ms, reconnect_backoff: 1s}
  vehicles:
    - name: v1
      link: {delay: 20ms}
timeline:
  - {at: 1s, client_data: {source: tcp, vehicles: {v1: {echo: latest}}, every: 10ms}}
  - {at: 3s, operator_misbehave: {bad_message: eof_mid_frame}}
  - {at: 3050ms, operator_misbehave: {}}
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
  for (const char* world : {outage_world, reorder_world, operator_world, locked_client_world}) {
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

// Each other mutant, the world that shows it, and the check that must catch it.
struct MutantCase {
  const char* name;
  const char* world;
  Mutant mutant;
  Check family;
};
const MutantCase mutant_cases[] = {
    {"default controller not applied", outage_world, Mutant::default_controller_not_applied, Check::safety_controller},
    {"stale pair accepted", reorder_world, Mutant::stale_pair_accepted, Check::latency_loop},
    {"delivery counted twice", outage_world, Mutant::delivered_counted_twice, Check::conservation},
    {"bad operator frame kept", operator_world, Mutant::operator_bad_frame_kept, Check::operator_port},
    {"keep-alive locks the source", operator_world, Mutant::keep_alive_locks_source, Check::operator_port},
    {"feedback fault lists stale", operator_world, Mutant::feedback_fault_lists_stale, Check::operator_feedback},
    {"locked client's pair kept", locked_client_world, Mutant::locked_client_pair_kept, Check::operator_port},
};

TEST(CampaignMutants, EachIsCaughtByItsCheck) {
  for (const MutantCase& c : mutant_cases) {
    const WorldOutcome outcome = check(c.world, c.mutant);
    EXPECT_TRUE(caught(outcome, c.family)) << c.name << ":\n" << describe(outcome);
  }
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

// An operator-side failure shrinks to a scenario whose own expectation fails under the mutant
// (judged by the scenario runner, not the oracle) and passes without it: a regression test.
TEST(CampaignShrink, OperatorFailuresShrinkToScenariosThatFailOnTheirOwn) {
  const std::pair<Mutant, Check> cases[] = {{Mutant::operator_bad_frame_kept, Check::operator_port},
                                            {Mutant::keep_alive_locks_source, Check::operator_port},
                                            {Mutant::feedback_fault_lists_stale, Check::operator_feedback}};
  for (const auto& [mutant, family] : cases) {
    std::string yaml;
    {
      const MutantOn on(mutant);
      const ShrinkResult shrunk = shrink(scenario::parse_scenario(operator_world, "operator.yaml"), {family, std::nullopt}, 100);
      ASSERT_EQ(shrunk.violation.check, family) << static_cast<int>(mutant);
      ASSERT_TRUE(shrunk.violation.regression.has_value()) << shrunk.violation.detail;
      yaml = regression_yaml(shrunk, "ocp_campaign check shrunk.yaml");
    }
    const scenario::Scenario regression = scenario::parse_scenario(yaml, "shrunk.yaml");
    auto verdicts = [&] { return scenario::evaluate(regression, scenario::run_scenario(regression, {})); };
    {
      const MutantOn on(mutant);
      EXPECT_FALSE(scenario::all_passed(verdicts())) << yaml;
    }
    EXPECT_TRUE(scenario::all_passed(verdicts())) << yaml;
  }
}

}  // namespace
}  // namespace ocp::campaign
