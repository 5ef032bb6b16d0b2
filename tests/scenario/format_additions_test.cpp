// The scenario format's additions for campaigns and hand-written regressions (issue #21 item
// 7): each passes on a world that does it, comes out FAILED on one that does not, and survives
// write_scenario_yaml → parse → write unchanged (a shrunk campaign world is written as YAML).
#include "scenario/write.hpp"
#include "scenario_test_support.hpp"

namespace ocp::scenario {
namespace {

using test::one_vehicle;
using test::only;
using test::run_text;

void expect_round_trip(const std::string& yaml) {
  const std::string written = write_scenario_yaml(parse_scenario(yaml, "inline.yaml"));
  EXPECT_EQ(write_scenario_yaml(parse_scenario(written, "written.yaml")), written) << written;
}

// --- never … until ----------------------------------------------------------------------
const char* const unplug_at_4s = "timeline:\n  - {at: 4s, name: unplug, gamepad: unplug}\n";

TEST(FormatAdditions, NeverUntilIgnoresWhatComesAfter) {
  const std::string yaml = one_vehicle(std::string(unplug_at_4s) + "expect:\n  faults:\n    - {fault: InputLost, never: true, until: 3s}\n");
  const auto outcome = run_text(yaml);
  EXPECT_TRUE(only(outcome).passed) << only(outcome).actual;
  EXPECT_EQ(only(outcome).title, "InputLost never raised until 3s");
  EXPECT_EQ(only(outcome).expected, "never active until 3s");
  expect_round_trip(yaml);
}

TEST(FormatAdditions, NeverUntilFailsOnARaiseInsideTheWindow) {
  const auto outcome = run_text(one_vehicle(std::string(unplug_at_4s) +
                                            "expect:\n  faults:\n    - {fault: InputLost, never: true, from: 1s, until: 5s}\n"));
  EXPECT_FALSE(only(outcome).passed);
  EXPECT_EQ(only(outcome).expected, "never active from 1s until 5s");
  EXPECT_EQ(only(outcome).actual, "raised 1 time(s), first on truck-1 at 4s");
}

TEST(FormatAdditions, NeverUntilMustComeAfterFrom) {
  EXPECT_THROW(parse_scenario(one_vehicle("expect:\n  faults:\n    - {fault: InputLost, never: true, from: 3s, until: 2s}\n"), "x.yaml"),
               ScenarioError);
  EXPECT_THROW(parse_scenario(one_vehicle("expect:\n  faults:\n    - {fault: InputLost, never: true, until: 9s}\n"), "x.yaml"),
               ScenarioError);
}

// --- always (stays active) ------------------------------------------------------------
TEST(FormatAdditions, AlwaysActiveUntilTheEnd) {
  const std::string yaml = one_vehicle(std::string(unplug_at_4s) +
                                       "expect:\n  faults:\n    - {fault: InputLost, always: true, from: unplug}\n");
  const auto outcome = run_text(yaml);
  EXPECT_TRUE(only(outcome).passed) << only(outcome).actual;
  EXPECT_EQ(only(outcome).title, "InputLost active on truck-1 from unplug until the end");
  EXPECT_EQ(only(outcome).actual, "active from 4s to the end");
  expect_round_trip(yaml);
}

TEST(FormatAdditions, AlwaysFailsWhenRaisedLate) {
  const auto outcome = run_text(one_vehicle(std::string(unplug_at_4s) +
                                            "expect:\n  faults:\n    - {fault: InputLost, always: true, from: 3s, until: 5s}\n"));
  EXPECT_FALSE(only(outcome).passed);
  EXPECT_EQ(only(outcome).actual, "not active at 3s (first raised at 4s)");
}

TEST(FormatAdditions, AlwaysFailsWhenClearedInsideTheWindow) {
  const auto outcome = run_text(one_vehicle(R"(timeline:
  - {at: 2s, gamepad: unplug}
  - {at: 4s, gamepad: replug}
expect:
  faults:
    - {fault: InputLost, always: true, from: 2s, until: end}
)"));
  EXPECT_FALSE(only(outcome).passed);
  EXPECT_EQ(only(outcome).actual, "cleared at 4s, inside the window");
}

// --- every frame in a window; controller fields; user data absent ---------------------------
const std::string constant_gamepad = "seed: 4\nduration: 4s\nworld:\n  gamepad: {constant: \"right_trigger=0.4 a=1\"}\n"
                                     "  vehicles:\n    - name: truck-1\n      link: {delay: 20ms}\n";

TEST(FormatAdditions, EveryFrameCarriesTheFieldsAndNoUserData) {
  const std::string yaml = constant_gamepad + R"(expect:
  delivered:
    - {after: 1s, within: 1s, every: true, controller: driving, fields: "right_trigger=0.4 a=1", no_user_data: true}
)";
  const auto outcome = run_text(yaml);
  EXPECT_TRUE(only(outcome).passed) << only(outcome).actual;
  EXPECT_NE(only(outcome).actual.find("control frames in the window, all did"), std::string::npos) << only(outcome).actual;
  expect_round_trip(yaml);
}

TEST(FormatAdditions, EveryFrameFailsOnTheFirstFrameThatDoesNot) {
  const auto outcome = run_text(constant_gamepad + R"(expect:
  delivered:
    - {after: 1s, within: 1s, every: true, controller: safe}
)");
  EXPECT_FALSE(only(outcome).passed);
  EXPECT_EQ(only(outcome).expected, "every control frame with controller safe (default or null) within 1s after 1s");
  EXPECT_EQ(only(outcome).actual.rfind("frame 1 in the window (at ", 0), 0u) << only(outcome).actual;
  EXPECT_NE(only(outcome).actual.find("did not: controller driving, user_data none"), std::string::npos) << only(outcome).actual;
}

TEST(FormatAdditions, FieldValueThatIsNotSent) {
  const auto outcome = run_text(constant_gamepad + R"(expect:
  delivered:
    - {after: 1s, within: 500ms, fields: "right_trigger=0.5"}
)");
  EXPECT_FALSE(only(outcome).passed);
  EXPECT_EQ(only(outcome).actual, "last frame in the window: controller driving (right_trigger=0.4), user_data none");
}

TEST(FormatAdditions, UserDataThatShouldBeAbsent) {
  const auto outcome = run_text(one_vehicle(R"(timeline:
  - {at: 2s, client_data: {source: plugin, vehicles: {truck-1: {user_data: {command: park}, echo: latest}}, every: 10ms}}
expect:
  delivered:
    - {after: 2100ms, within: 1s, every: true, no_user_data: true}
)"));
  EXPECT_FALSE(only(outcome).passed);
  EXPECT_NE(only(outcome).actual.find("user_data {\"command\":\"park\"}"), std::string::npos) << only(outcome).actual;
}

TEST(FormatAdditions, EveryFrameWithNoFrameInTheWindowChecksNothing) {
  // Disconnected, and not back before the reconnect backoff: no frame goes to the vehicle.
  const auto outcome = run_text(R"(seed: 4
duration: 4s
world:
  reconnect_backoff: 2s
  vehicles:
    - name: truck-1
timeline:
  - {at: 1s, disconnect: {}}
expect:
  delivered:
    - {after: 1200ms, within: 500ms, every: true, controller: safe}
)");
  EXPECT_FALSE(only(outcome).passed);
  EXPECT_EQ(only(outcome).actual, "no control frame reached truck-1 in the window: nothing checked");
}

TEST(FormatAdditions, BadFieldsAreRefused) {
  for (const char* fields : {"right_trigger=2", "elbow=1", "a=yes", ""}) {
    EXPECT_THROW(parse_scenario(constant_gamepad + "expect:\n  delivered:\n    - {after: 1s, within: 1s, fields: \"" +
                                    fields + "\"}\n", "x.yaml"),
                 ScenarioError) << fields;
  }
  EXPECT_THROW(parse_scenario(constant_gamepad + "expect:\n  delivered:\n    - {after: 1s, within: 1s, user_data: 1, no_user_data: true}\n",
                              "x.yaml"),
               ScenarioError);
}

// --- client data for a vehicle the world does not have (SPEC §4.2) --------------------------
const std::string unknown_vehicle_data = one_vehicle(R"(timeline:
  - {at: 2s, name: command, client_data: {source: plugin, vehicles: {truck-9: {user_data: {command: stop}}, truck-1: {user_data: {command: park}, echo: latest}}, every: 10ms}}
expect:
  delivered:
)");

TEST(FormatAdditions, ClientDataForAnUnknownVehicleIsWarnedAboutAndIgnored) {
  const std::string yaml = unknown_vehicle_data + "    - {after: command, within: 100ms, user_data: {command: park}}\n";
  const auto outcome = run_text(yaml);
  ASSERT_EQ(outcome.scenario.warnings.size(), 1u);
  EXPECT_NE(outcome.scenario.warnings[0].find("inline.yaml:9:"), std::string::npos) << outcome.scenario.warnings[0];
  EXPECT_NE(outcome.scenario.warnings[0].find("vehicle 'truck-9', which the world does not have"), std::string::npos);
  EXPECT_NE(outcome.scenario.warnings[0].find("did you mean 'truck-1'?"), std::string::npos);
  EXPECT_TRUE(only(outcome).passed) << only(outcome).actual;
  expect_round_trip(yaml);
}

TEST(FormatAdditions, TheUnknownVehiclesEntryReachesNobody) {
  const auto outcome = run_text(unknown_vehicle_data + "    - {after: command, within: 100ms, user_data: {command: stop}}\n");
  EXPECT_FALSE(only(outcome).passed);
  EXPECT_EQ(only(outcome).actual, "last frame in the window: controller driving, user_data {\"command\":\"park\"}");
}

// --- a world that must refuse to start ---------------------------------------------------
const std::string two_vehicles_without_fleet = R"(seed: 1
duration: 2s
world:
  fleet: false
  vehicles:
    - {name: truck-1}
    - {name: truck-2}
expect:
)";

TEST(FormatAdditions, RefusesToStart) {
  const std::string yaml = two_vehicles_without_fleet + "  refuses_to_start: without a fleet configuration\n";
  const auto outcome = run_text(yaml);
  EXPECT_TRUE(only(outcome).passed) << only(outcome).actual;
  EXPECT_NE(only(outcome).actual.find("cannot link vehicle 'truck-2': without a fleet configuration"), std::string::npos) << only(outcome).actual;
  expect_round_trip(yaml);
}

TEST(FormatAdditions, RefusesToStartForAnotherReason) {
  const auto outcome = run_text(two_vehicles_without_fleet + "  refuses_to_start: vehicle name\n");
  EXPECT_FALSE(only(outcome).passed);
  EXPECT_EQ(only(outcome).actual.rfind("refused: Invalid argument: cannot link vehicle", 0), 0u) << only(outcome).actual;
}

TEST(FormatAdditions, AWorldThatStartsFailsRefusesToStart) {
  const auto outcome = run_text(one_vehicle("expect:\n  refuses_to_start: anything\n"));
  EXPECT_FALSE(only(outcome).passed);
  EXPECT_EQ(only(outcome).actual, "the world started");
}

TEST(FormatAdditions, RefusesToStartIsTheOnlyExpectation) {
  EXPECT_THROW(parse_scenario(two_vehicles_without_fleet + "  refuses_to_start: x\n  invariants: [no_stale_pair_after_reconnect]\n",
                              "x.yaml"),
               ScenarioError);
  // Without it, the same world is the parser's error, as before.
  EXPECT_THROW(parse_scenario(two_vehicles_without_fleet + "  invariants: [no_stale_pair_after_reconnect]\n", "x.yaml"),
               ScenarioError);
}

}  // namespace
}  // namespace ocp::scenario

namespace ocp::scenario {
namespace {

// --- notable events: source lock and conflict, connection closes ---------------------------
const std::string two_sources = test::one_vehicle(R"(timeline:
  - {at: 2s, name: plugin_starts, client_data: {source: plugin, vehicles: {truck-1: {user_data: {a: 1}}}, every: 50ms}}
  - {at: 3s, name: webview_too, client_data: {source: webview, vehicles: {truck-1: {user_data: {a: 2}}}}}
expect:
  events:
)");

TEST(FormatAdditions, SourceLockAndConflict) {
  const std::string yaml = two_sources + R"(    - {event: source_locked, source: plugin, after: plugin_starts, within: 10ms}
    - {event: source_conflict, locked: plugin, source: webview, after: webview_too, within: 10ms}
    - {event: source_conflict, never: true, until: 2900ms}
)";
  const auto outcome = run_text(yaml);
  ASSERT_EQ(outcome.verdicts.size(), 3u);
  for (const Verdict& verdict : outcome.verdicts) EXPECT_TRUE(verdict.passed) << verdict.title << ": " << verdict.actual;
  EXPECT_EQ(outcome.verdicts[1].actual, "source_conflict locked plugin offending webview at 3s");
  expect_round_trip(yaml);
}

TEST(FormatAdditions, SourceEventsThatDidNotHappenSo) {
  const auto outcome = run_text(two_sources + R"(    - {event: source_locked, source: webview, after: 0s, within: 5s}
    - {event: source_conflict, never: true}
)");
  ASSERT_EQ(outcome.verdicts.size(), 2u);
  EXPECT_FALSE(outcome.verdicts[0].passed);
  EXPECT_EQ(outcome.verdicts[0].actual, "none in the window; nearest: source_locked plugin at 2s");
  EXPECT_FALSE(outcome.verdicts[1].passed);
  EXPECT_EQ(outcome.verdicts[1].actual, "1 time(s), first: source_conflict locked plugin offending webview at 3s");
}

const std::string disconnect_at_1s = test::one_vehicle(R"(timeline:
  - {at: 1s, name: cut, disconnect: {}}
expect:
  events:
)");

TEST(FormatAdditions, ConnectionClosedWithItsReason) {
  const auto probe = run_text(disconnect_at_1s + "    - {event: connection_closed, vehicle: truck-1, after: cut, within: 100ms}\n");
  ASSERT_TRUE(only(probe).passed) << only(probe).actual;
  const std::string yaml = disconnect_at_1s + "    - {event: connection_closed, vehicle: truck-1, reason: closed, after: cut, within: 100ms}\n";
  const auto outcome = run_text(yaml);
  EXPECT_TRUE(only(outcome).passed) << only(outcome).actual;
  expect_round_trip(yaml);
}

TEST(FormatAdditions, ConnectionClosedForAnotherReason) {
  const auto outcome = run_text(disconnect_at_1s +
                                "    - {event: connection_closed, vehicle: truck-1, reason: frame too large, after: cut, within: 100ms}\n");
  EXPECT_FALSE(only(outcome).passed);
  EXPECT_EQ(only(outcome).actual.rfind("none in the window; nearest: connection_closed on truck-1 '", 0), 0u) << only(outcome).actual;
}

TEST(FormatAdditions, BadEventExpectationsAreRefused) {
  for (const char* item : {"{event: source_locked, vehicle: truck-1, after: 1s, within: 1s}",
                           "{event: connection_closed, source: tcp, after: 1s, within: 1s}",
                           "{event: source_locked, never: true, after: 1s}", "{event: source_locked, from: 1s, within: 1s}",
                           "{event: lock, after: 1s, within: 1s}", "{event: source_locked, source: usb, after: 1s, within: 1s}"}) {
    EXPECT_THROW(parse_scenario(test::one_vehicle(std::string("expect:\n  events:\n    - ") + item + "\n"), "x.yaml"), ScenarioError)
        << item;
  }
}

}  // namespace
}  // namespace ocp::scenario

namespace ocp::scenario {
namespace {

// --- broken responses from the in-process vehicle client (SPEC §2: the Streamer closes) -------
struct BadResponseCase {
  const char* kind;
  const char* reason;   // what the Streamer's close reason says
};

class BadResponses : public ::testing::TestWithParam<BadResponseCase> {};

std::string bad_response_world(const std::string& kind, const std::string& expectation) {
  return test::one_vehicle("timeline:\n  - {at: 1s, name: broken, misbehave: {bad_response: " + kind +
                           "}}\n  - {at: 2s, name: fixed, misbehave: {bad_response: none}}\nexpect:\n  events:\n    - " +
                           expectation + "\n");
}

TEST_P(BadResponses, TheStreamerClosesTheConnectionSayingWhy) {
  const std::string yaml = bad_response_world(
      GetParam().kind, std::string("{event: connection_closed, vehicle: truck-1, reason: \"") + GetParam().reason +
                           "\", after: broken, within: 50ms}");
  const auto outcome = run_text(yaml);
  EXPECT_TRUE(only(outcome).passed) << only(outcome).actual;
  expect_round_trip(yaml);
}

TEST_P(BadResponses, NoCloseBeforeTheMisbehaviour) {
  const auto outcome = run_text(bad_response_world(GetParam().kind, "{event: connection_closed, never: true}"));
  EXPECT_FALSE(only(outcome).passed);
  EXPECT_NE(only(outcome).actual.find("first: connection_closed on truck-1 '"), std::string::npos) << only(outcome).actual;
}

INSTANTIATE_TEST_SUITE_P(FormatAdditions, BadResponses,
                         ::testing::Values(BadResponseCase{"missing_field", "missing field: ack_time_mac"},
                                           BadResponseCase{"wrong_type", "wrong type: ack_time"},
                                           BadResponseCase{"not_an_object", "not a JSON object"},
                                           BadResponseCase{"ack_time_out_of_range", "out of range: ack_time"},
                                           BadResponseCase{"eof_mid_frame", "truncated frame: stream ended inside"}),
                         [](const auto& info) { return std::string(info.param.kind); });

}  // namespace
}  // namespace ocp::scenario

namespace ocp::scenario {
namespace {

// --- a second vehicle connection (SPEC §3.1: accepted and closed at once) --------------------
const std::string second_connection_world = test::one_vehicle(R"(timeline:
  - {at: 1s, name: intruder, misbehave: {second_connection: true}}
expect:
  events:
)");

TEST(FormatAdditions, SecondConnectionIsRefusedAndTheFirstStays) {
  const std::string yaml = second_connection_world + R"(    - {event: connection_refused, vehicle: truck-1, after: intruder, within: 10ms}
    - {event: connection_closed, never: true}
)";
  const auto outcome = run_text(yaml);
  ASSERT_EQ(outcome.verdicts.size(), 2u);
  for (const Verdict& verdict : outcome.verdicts) EXPECT_TRUE(verdict.passed) << verdict.title << ": " << verdict.actual;
  expect_round_trip(yaml);
}

TEST(FormatAdditions, NoRefusalWithoutASecondConnection) {
  const auto outcome = run_text(second_connection_world + "    - {event: connection_refused, never: true}\n");
  EXPECT_FALSE(only(outcome).passed);
  EXPECT_EQ(only(outcome).actual.rfind("1 time(s), first: connection_refused on truck-1 '", 0), 0u) << only(outcome).actual;
}

}  // namespace
}  // namespace ocp::scenario
