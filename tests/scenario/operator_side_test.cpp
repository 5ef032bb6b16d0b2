// The operator side in scenarios (issue #21 item 7): an in-process operator client on the
// Player's :4001 port makes the Player's VehicleOcpShared visible (expect.feedback: a field,
// the sender and receiver fault lists), and misbehaves on that port on the timeline
// (operator_misbehave), the Player's reaction judged through expect.events on the operator
// wire. Each expectation passes on a world that does it and comes out FAILED on one that
// does not; the new sections survive write_scenario_yaml → parse → write unchanged.
#include "scenario/write.hpp"
#include "scenario_test_support.hpp"

namespace ocp::scenario {
namespace {

using test::only;
using test::run_text;

// One vehicle, the drive script, the operator client connected; `rest` adds timeline and expect.
std::string with_operator(const std::string& rest, const std::string& duration = "8s") {
  return "seed: 4\nduration: " + duration +
         "\nworld:\n  gamepad: drive\n  operator_client: {connect: true}\n  vehicles:\n    - name: truck-1\n"
         "      link: {delay: 20ms}\n" +
         rest;
}

void expect_operator_round_trip(const std::string& yaml) {
  const std::string written = write_scenario_yaml(parse_scenario(yaml, "inline.yaml"));
  EXPECT_EQ(write_scenario_yaml(parse_scenario(written, "written.yaml")), written) << written;
}

void expect_parse_error(const std::string& yaml, const std::string& text) {
  try {
    parse_scenario(yaml, "x.yaml");
    ADD_FAILURE() << "no error, expected: " << text;
  } catch (const ScenarioError& error) {
    EXPECT_NE(std::string(error.what()).find(text), std::string::npos) << error.what();
  }
}

const char* const unplug_at_3s = "timeline:\n  - {at: 3s, gamepad: unplug}\n";

// --- the operator client -----------------------------------------------------------------
TEST(OperatorSide, TheClientReadsFeedbackAndStaysConnected) {
  const std::string yaml = with_operator(R"(expect:
  events:
    - {event: connection_closed, wire: operator, never: true}
  feedback:
    - {vehicle: truck-1, field: is_monitor, equals: false, from: 500ms}
)");
  const auto outcome = run_text(yaml);
  ASSERT_EQ(outcome.verdicts.size(), 2u);
  for (const Verdict& verdict : outcome.verdicts) EXPECT_TRUE(verdict.passed) << verdict.title << ": " << verdict.actual;
  EXPECT_EQ(outcome.verdicts[1].actual, "is_monitor = false throughout");
  expect_operator_round_trip(yaml);
}

TEST(OperatorSide, SilentFromTheStartIsClosedByTheReadTimeout) {
  // No keep-alive ever: the Player's read timeout (SPEC §2, 2 s) closes the connection.
  const auto outcome = run_text(with_operator(R"(timeline:
  - {at: 0s, operator_misbehave: {silent: true}}
expect:
  events:
    - {event: connection_closed, wire: operator, never: true}
)"));
  EXPECT_FALSE(only(outcome).passed);
  EXPECT_NE(only(outcome).actual.find("read timeout"), std::string::npos) << only(outcome).actual;
}

// --- feedback fields ------------------------------------------------------------------------
TEST(OperatorSide, FeedbackFieldFailsWithTheValueSent) {
  const auto outcome = run_text(with_operator(R"(expect:
  feedback:
    - {vehicle: truck-1, field: is_monitor, equals: true, from: 1s, until: 2s}
)"));
  EXPECT_FALSE(only(outcome).passed);
  EXPECT_EQ(only(outcome).expected, "is_monitor = true on truck-1 from 1s until 2s");
  EXPECT_EQ(only(outcome).actual, "is_monitor = false at 1s");
}

TEST(OperatorSide, FeedbackFieldInsideTheEntryAndAbsentOnes) {
  // last_remote_input.buttons.start: the drive script presses start first, then drives on.
  const std::string yaml = with_operator(R"(timeline:
  - {at: 3s, gamepad: unplug}
expect:
  feedback:
    - {vehicle: truck-1, field: missing_cameras, equals: null, at: 2s}
    - {vehicle: truck-1, field: vehicle_data.no_such_member, equals: 1, at: 2s}
)");
  const auto outcome = run_text(yaml);
  ASSERT_EQ(outcome.verdicts.size(), 2u);
  EXPECT_TRUE(outcome.verdicts[0].passed) << outcome.verdicts[0].actual;
  EXPECT_EQ(outcome.verdicts[0].actual, "missing_cameras = null");
  EXPECT_FALSE(outcome.verdicts[1].passed);
  EXPECT_EQ(outcome.verdicts[1].actual, "vehicle_data.no_such_member = absent at 2s");
  expect_operator_round_trip(yaml);
}

TEST(OperatorSide, FeedbackWindowFailsAtTheFirstChangeInsideIt) {
  const auto outcome = run_text(with_operator(std::string(unplug_at_3s) + R"(expect:
  feedback:
    - {vehicle: truck-1, sender_fault: [], from: 1s, until: 5s}
)"));
  EXPECT_FALSE(only(outcome).passed);
  // The Player's frame at the unplug already carries InputLost (frames every 10 ms from 0 s).
  EXPECT_EQ(only(outcome).actual, "sender_fault = [\"InputLost\"] at 3s");
}

// --- the fault lists ------------------------------------------------------------------------
TEST(OperatorSide, FaultListsAsSeenInTheFeedback) {
  // Unplugged: InputLost on the Player's side (sender), OperatorStationHasError on the
  // Streamer's (receiver) once it reached it (SPEC §6).
  const std::string yaml = with_operator(std::string(unplug_at_3s) + R"(expect:
  feedback:
    - {vehicle: truck-1, sender_fault: [], receiver_fault: [], at: 2s}
    - {vehicle: truck-1, sender_fault: [InputLost], receiver_fault: [OperatorStationHasError], from: 4s, until: 8s}
)");
  const auto outcome = run_text(yaml);
  ASSERT_EQ(outcome.verdicts.size(), 2u);
  for (const Verdict& verdict : outcome.verdicts) EXPECT_TRUE(verdict.passed) << verdict.title << ": " << verdict.actual;
  EXPECT_EQ(outcome.verdicts[0].title, "feedback on truck-1: sender_fault = [] receiver_fault = [] at 2s");
  expect_operator_round_trip(yaml);
}

TEST(OperatorSide, FaultListFailsOnAFaultNotExpected) {
  const auto outcome = run_text(with_operator(std::string(unplug_at_3s) + R"(expect:
  feedback:
    - {vehicle: truck-1, sender_fault: [InputLost], receiver_fault: [], at: 5s}
)"));
  EXPECT_FALSE(only(outcome).passed);
  EXPECT_EQ(only(outcome).expected,
            "sender_fault = [\"InputLost\"] (as a set), receiver_fault = [] (as a set) on truck-1 at 5s");
  EXPECT_EQ(only(outcome).actual, "receiver_fault = [\"OperatorStationHasError\"] at 5s");
}

TEST(OperatorSide, FaultListsNameFaultsOfTheirSide) {
  expect_parse_error(with_operator("expect:\n  feedback:\n    - {sender_fault: [NoControlMessage], at: 1s}\n"),
                     "unknown sender_fault fault (an operator fault) 'NoControlMessage'");
  expect_parse_error(with_operator("expect:\n  feedback:\n    - {receiver_fault: [InputLost], at: 1s}\n"),
                     "receiver_fault fault (a vehicle fault)");
  expect_parse_error(with_operator("expect:\n  feedback:\n    - {field: vehicle_dta.x, equals: 1, at: 1s}\n"),
                     "did you mean 'vehicle_data'");
  expect_parse_error(with_operator("expect:\n  feedback:\n    - {field: is_monitor, at: 1s}\n"), "equals");
  expect_parse_error(with_operator("expect:\n  feedback:\n    - {field: is_monitor, equals: false}\n"),
                     "needs at, or from (and until)");
  expect_parse_error(with_operator("expect:\n  feedback:\n    - {field: is_monitor, equals: false, at: 9s}\n"),
                     "after the end of the run");
  expect_parse_error(test::one_vehicle("expect:\n  feedback:\n    - {field: is_monitor, equals: false, at: 1s}\n"),
                     "world.operator_client: {connect: true}");
}

// --- misbehaviours on the operator port and the Player's reaction ----------------------------
struct OperatorMisbehaviourCase {
  const char* misbehave;   // the operator_misbehave switches
  const char* reason;      // what the Player's close reason says (SPEC §2)
};

class OperatorMisbehaviourCloses : public ::testing::TestWithParam<OperatorMisbehaviourCase> {};

TEST_P(OperatorMisbehaviourCloses, ThePlayerClosesWithItsReason) {
  const std::string yaml = with_operator(std::string("timeline:\n  - {at: 3s, name: bad, operator_misbehave: {") +
                                         GetParam().misbehave + "}}\nexpect:\n  events:\n" +
                                         "    - {event: connection_closed, wire: operator, reason: \"" + GetParam().reason +
                                         "\", after: bad, within: 3s}\n");
  const auto outcome = run_text(yaml);
  EXPECT_TRUE(only(outcome).passed) << only(outcome).actual;
  expect_operator_round_trip(yaml);
}

TEST_P(OperatorMisbehaviourCloses, AConnectionKeptFailsTheExpectation) {
  const auto outcome = run_text(with_operator(std::string("timeline:\n  - {at: 3s, operator_misbehave: {") +
                                              GetParam().misbehave + "}}\nexpect:\n  events:\n" +
                                              "    - {event: connection_closed, wire: operator, never: true}\n"));
  EXPECT_FALSE(only(outcome).passed);
  EXPECT_NE(only(outcome).actual.find(GetParam().reason), std::string::npos) << only(outcome).actual;
}

INSTANTIATE_TEST_SUITE_P(OperatorSide, OperatorMisbehaviourCloses,
                         ::testing::Values(OperatorMisbehaviourCase{"malformed_json: true", "malformed JSON"},
                                           OperatorMisbehaviourCase{"bad_message: not_an_object", "not a JSON object"},
                                           OperatorMisbehaviourCase{"bad_message: wrong_type", "wrong type"},
                                           OperatorMisbehaviourCase{"bad_message: eof_mid_frame", "truncated frame"},
                                           OperatorMisbehaviourCase{"silent: true", "read timeout"}));

TEST(OperatorSide, OversizedFramesAreDrainedAndTheConnectionKept) {
  const std::string yaml = with_operator(R"(timeline:
  - {at: 3s, operator_misbehave: {oversized_frames: true}}
expect:
  events:
    - {event: connection_closed, wire: operator, never: true}
  feedback:
    - {vehicle: truck-1, field: is_monitor, equals: false, from: 3s}
)");
  const auto outcome = run_text(yaml);
  ASSERT_EQ(outcome.verdicts.size(), 2u);
  for (const Verdict& verdict : outcome.verdicts) EXPECT_TRUE(verdict.passed) << verdict.title << ": " << verdict.actual;
  expect_operator_round_trip(yaml);
}

TEST(OperatorSide, OversizedFramesCloseNothingAnExpectedCloseFails) {
  const auto outcome = run_text(with_operator(R"(timeline:
  - {at: 3s, operator_misbehave: {oversized_frames: true}}
expect:
  events:
    - {event: connection_closed, wire: operator, after: 3s, within: 4s}
)"));
  EXPECT_FALSE(only(outcome).passed);
  EXPECT_EQ(only(outcome).actual, "none in the window");
}

TEST(OperatorSide, ASecondConnectionIsRefused) {
  const std::string yaml = with_operator(R"(timeline:
  - {at: 2s, name: second, operator_misbehave: {second_connection: true}}
expect:
  events:
    - {event: connection_refused, wire: operator, reason: "already connected", after: second, within: 10ms}
    - {event: connection_closed, wire: operator, never: true}
)");
  const auto outcome = run_text(yaml);
  ASSERT_EQ(outcome.verdicts.size(), 2u);
  for (const Verdict& verdict : outcome.verdicts) EXPECT_TRUE(verdict.passed) << verdict.title << ": " << verdict.actual;
  expect_operator_round_trip(yaml);
}

TEST(OperatorSide, ASecondConnectionFailsNeverRefused) {
  const auto outcome = run_text(with_operator(R"(timeline:
  - {at: 2s, operator_misbehave: {second_connection: true}}
expect:
  events:
    - {event: connection_refused, wire: operator, never: true}
)"));
  EXPECT_FALSE(only(outcome).passed);
  EXPECT_NE(only(outcome).actual.find("connection_refused on player"), std::string::npos) << only(outcome).actual;
}

TEST(OperatorSide, WellBehavedAgainTheClientReconnects) {
  // docs/scenarios.md's example: closed for malformed JSON at 3 s (the keep-alive due then
  // follows the event), well-behaved from 3.5 s: the reconnect 1 s later holds and reads on.
  const auto outcome = run_text(with_operator(R"(timeline:
  - {at: 3s, name: garbage, operator_misbehave: {malformed_json: true}}
  - {at: 3500ms, operator_misbehave: {}}
expect:
  events:
    - {event: connection_closed, wire: operator, reason: malformed JSON, after: garbage, within: 1.5s}
    - {event: connection_closed, wire: operator, never: true, from: 3500ms}
  feedback:
    - {vehicle: truck-1, field: is_monitor, equals: false, from: 6s}
)"));
  ASSERT_EQ(outcome.verdicts.size(), 3u);
  EXPECT_EQ(outcome.verdicts[0].actual.rfind("connection_closed on player 'malformed JSON", 0), 0u) << outcome.verdicts[0].actual;
  for (const Verdict& verdict : outcome.verdicts) EXPECT_TRUE(verdict.passed) << verdict.title << ": " << verdict.actual;
}

// expect.events takes within: [min, max] as expect.faults does (issue #35); an event before
// min is the near miss the verdict names.
TEST(OperatorSide, EventsWithinAWindow) {
  const std::string yaml = with_operator(R"(timeline:
  - {at: 3s, name: garbage, operator_misbehave: {malformed_json: true}}
  - {at: 3500ms, operator_misbehave: {}}
expect:
  events:
    - {event: connection_closed, wire: operator, reason: malformed JSON, after: garbage, within: [0ms, 10ms]}
    - {event: connection_closed, wire: operator, reason: malformed JSON, after: garbage, within: [100ms, 1s]}
)");
  const auto outcome = run_text(yaml);
  ASSERT_EQ(outcome.verdicts.size(), 2u);
  EXPECT_TRUE(outcome.verdicts[0].passed) << outcome.verdicts[0].actual;
  EXPECT_EQ(outcome.verdicts[0].title.find("within [0ms"), std::string::npos) << outcome.verdicts[0].title;
  EXPECT_FALSE(outcome.verdicts[1].passed);
  EXPECT_EQ(outcome.verdicts[1].expected, "connection_closed in [3.1s, 4s]") << outcome.verdicts[1].expected;
  EXPECT_NE(outcome.verdicts[1].actual.find("nearest: connection_closed on player"), std::string::npos)
      << outcome.verdicts[1].actual;
  expect_operator_round_trip(yaml);
  expect_parse_error(with_operator("expect:\n  events:\n    - {event: source_locked, after: 1s, within: [2s, 1s]}\n"),
                     "within: max < min");
}

// With an operator client, client data of source tcp goes through its connection: it stops
// while the client is away, and the Player (tcp locked, no client) returns no pair (SPEC §4.3
// Decision): InvalidMac a Player frame plus the 20 ms link delay after the hang-up. Before
// issue #35 the data reached the Player without a connection and the old pair kept coming.
TEST(OperatorSide, TcpClientDataGoesThroughTheOperatorClient) {
  const std::string yaml = R"(seed: 4
duration: 6s
world:
  gamepad: drive
  operator_client: {connect: true, keep_alive_period: 100ms, reconnect_backoff: 1s}
  vehicles:
    - name: truck-1
      link: {delay: 20ms}
timeline:
  - {at: 1s, name: echo, client_data: {source: tcp, vehicles: {truck-1: {echo: latest}}, every: 10ms}}
  - {at: 3s, name: hang_up, operator_misbehave: {bad_message: eof_mid_frame}}
  - {at: 3050ms, operator_misbehave: {}}
expect:
  events:
    - {event: source_locked, source: tcp, after: echo, within: 10ms}
  faults:
    - fault: InvalidMac
      raised: {after: hang_up, within: [20ms, 40ms]}
      cleared: {after: hang_up, within: [1000ms, 1060ms]}
)";
  const auto outcome = run_text(yaml);
  ASSERT_EQ(outcome.verdicts.size(), 3u);
  for (const Verdict& verdict : outcome.verdicts) EXPECT_TRUE(verdict.passed) << verdict.title << ": " << verdict.actual;
}

// SPEC §4.2 Decision: a web view call with a bare entry gets its pair injected and locks the
// source; the loop keeps turning while it sends. Before issue #35 it was a keep-alive: no lock.
TEST(OperatorSide, WebviewBareEntriesLockAndKeepTheLoopClosed) {
  const std::string yaml = test::one_vehicle(R"(timeline:
  - {at: 1s, name: page, client_data: {source: webview, vehicles: {truck-1: {}}, every: 10ms}}
expect:
  events:
    - {event: source_locked, source: webview, after: page, within: 10ms}
  faults:
    - {fault: InvalidMac, never: true, from: 500ms}
    - {fault: HighLatency, never: true}
)");
  const auto outcome = run_text(yaml);
  ASSERT_EQ(outcome.verdicts.size(), 3u);
  for (const Verdict& verdict : outcome.verdicts) EXPECT_TRUE(verdict.passed) << verdict.title << ": " << verdict.actual;
}

TEST(OperatorSide, OperatorMisbehaviourNeedsTheClientAndValidSettings) {
  expect_parse_error(test::one_vehicle("timeline:\n  - {at: 1s, operator_misbehave: {silent: true}}\nexpect:\n"
                                       "  faults:\n    - {fault: InputLost, never: true}\n"),
                     "operator_misbehave needs an operator client");
  expect_parse_error(with_operator("timeline:\n  - {at: 1s, operator_misbehave: {bad_message: wrong}}\nexpect:\n"
                                   "  faults:\n    - {fault: InputLost, never: true}\n"),
                     "unknown bad_message 'wrong'");
  const std::string zero = "seed: 4\nduration: 2s\nworld:\n  operator_client: {connect: true, keep_alive_period: 0s}\n"
                           "  vehicles:\n    - name: truck-1\nexpect:\n  faults:\n    - {fault: InputLost, never: true}\n";
  expect_parse_error(zero, "keep_alive_period must be > 0 and <= 60s");
}

}  // namespace
}  // namespace ocp::scenario
