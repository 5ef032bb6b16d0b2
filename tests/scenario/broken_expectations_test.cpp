// Deliberately wrong expectations must come out FAILED, and say expected against actual —
// one test per verdict kind.
#include "ocp/json_codec.hpp"
#include "scenario/observer.hpp"
#include "scenario_test_support.hpp"

namespace ocp::scenario {
namespace {

using test::one_vehicle;
using test::only;
using test::run_text;

TEST(BrokenExpectations, FaultEdgeTooEarlyWindow) {
  const auto outcome = run_text(one_vehicle(R"(timeline:
  - {at: 2s, name: unplug, gamepad: unplug}
expect:
  faults:
    - {fault: InputLost, raised: {after: unplug, within: [500ms, 1s]}}
)"));
  const Verdict& verdict = only(outcome);
  EXPECT_FALSE(verdict.passed);
  EXPECT_EQ(verdict.expected, "raised within [500ms, 1s] after unplug");
  EXPECT_EQ(verdict.actual, "raised 0ms after unplug (at 2s)");
}

TEST(BrokenExpectations, FaultEdgeThatNeverHappens) {
  const auto outcome = run_text(one_vehicle(R"(expect:
  faults:
    - {fault: CameraLost, raised: {after: 1s, within: 1s}}
)"));
  EXPECT_FALSE(only(outcome).passed);
  EXPECT_EQ(only(outcome).actual, "never raised after 1s");
}

TEST(BrokenExpectations, NeverThatHappens) {
  const auto outcome = run_text(one_vehicle(R"(timeline:
  - {at: 2s, gamepad: unplug}
expect:
  faults:
    - {fault: InputLost, never: true}
)"));
  EXPECT_FALSE(only(outcome).passed);
  EXPECT_EQ(only(outcome).expected, "never raised");
  EXPECT_EQ(only(outcome).actual, "raised 1 time(s), first on truck-1 at 2s");
}

TEST(BrokenExpectations, StateAtAnInstant) {
  const auto outcome = run_text(one_vehicle(R"(expect:
  faults:
    - {fault: VehicleControlInactive, at: 3s, active_on: [truck-1]}
)"));
  EXPECT_FALSE(only(outcome).passed);
  EXPECT_EQ(only(outcome).expected, "truck-1=active");
  EXPECT_EQ(only(outcome).actual, "truck-1=inactive");
}

TEST(BrokenExpectations, Threshold) {
  const auto outcome = run_text(one_vehicle(R"(expect:
  thresholds:
    latency_ms: ["p(99) < 5"]
)"));
  EXPECT_FALSE(only(outcome).passed);
  EXPECT_EQ(only(outcome).expected, "p(99) < 5");
  EXPECT_EQ(only(outcome).actual.rfind("p(99) = ", 0), 0u) << only(outcome).actual;
}

TEST(BrokenExpectations, DeliveryOfTheWrongUserData) {
  const auto outcome = run_text(one_vehicle(R"(timeline:
  - {at: 2s, name: command, client_data: {source: plugin, vehicles: {truck-1: {user_data: {command: park}, echo: latest}}, every: 10ms}}
expect:
  delivered:
    - {after: command, within: 100ms, user_data: {command: drive}}
)"));
  EXPECT_FALSE(only(outcome).passed);
  EXPECT_EQ(only(outcome).expected, "a control frame with user_data {\"command\":\"drive\"} within 100ms after command");
  EXPECT_EQ(only(outcome).actual, "last frame in the window: controller driving, user_data {\"command\":\"park\"}");
}

TEST(BrokenExpectations, InvariantWithNothingToCheck) {
  const auto outcome = run_text(one_vehicle(R"(expect:
  invariants: [no_stale_pair_after_reconnect]
)"));
  EXPECT_FALSE(only(outcome).passed);
  EXPECT_EQ(only(outcome).actual, "no reconnect happened: nothing checked");
}

// The Streamer never breaks the safety invariants, so their FAILED verdicts are shown on a
// hand-made event stream: the Observer sees exactly what the World would publish.
struct HandMadeStream {
  EventBus bus;
  Observer observer{bus, ObserverOptions{true, true, {}, {}}};
  void publish(SimTime time, EventBody body) { bus.publish(Event{time, Component{ComponentKind::streamer, "truck-1"}, std::move(body)}); }
  void control(SimTime time, std::uint64_t ack_time, const Controller& controller) {
    OcpControlMessage message;
    message.controller = controller;
    message.ack = AckPair{ack_time, 1};
    payload_.clear();
    encode_control_message(message, payload_);
    WireFrame frame;
    frame.payload = payload_;
    frame.ack = message.ack;
    publish(time, frame);
  }
  std::vector<Verdict> judge(Invariant invariant) {
    Scenario scenario = parse_scenario(one_vehicle("expect:\n  invariants: [" + std::string(invariant_name(invariant)) + "]\n"), "x.yaml");
    RunResult run;
    run.observations = observer.observations();
    return evaluate(scenario, run);
  }
  std::string payload_;
};

TEST(BrokenExpectations, ControllerInvariantFailsOnARealControllerUnderAFault) {
  HandMadeStream stream;
  stream.publish(SimTime{10'000}, FaultEvent{FaultSide::vehicle, FaultId::HighLatency, true, "truck-1"});
  stream.control(SimTime{10'000}, 5, Controller{});                       // default: fine
  Controller driving;
  driving.axes.right_trigger = 0.5;
  stream.control(SimTime{20'000}, 6, driving);                            // the violation
  const auto verdicts = stream.judge(Invariant::default_controller_during_control_fault);
  ASSERT_EQ(verdicts.size(), 1u);
  EXPECT_FALSE(verdicts[0].passed);
  EXPECT_EQ(verdicts[0].actual, "1 of 2 frames violated; first at 0.02s on truck-1: non-default controller while High Latency active");
}

TEST(BrokenExpectations, StalePairInvariantFailsOnAnOldPairAfterReconnect) {
  HandMadeStream stream;
  const CloseReason reason{make_error_code(PeerError::closed_by_peer), "gone"};
  stream.publish(SimTime{0}, ConnectionEvent{Wire::vehicle, ConnectionChange::opened, "pipe", nullptr});
  stream.control(SimTime{10'000}, 10'000, Controller{});
  stream.publish(SimTime{15'000}, ConnectionEvent{Wire::vehicle, ConnectionChange::closed, "pipe", &reason});
  stream.publish(SimTime{30'000}, ConnectionEvent{Wire::vehicle, ConnectionChange::opened, "pipe", nullptr});
  stream.control(SimTime{40'000}, 40'000, Controller{});
  WireFrame stale;
  stale.kind = WireMessageKind::vehicle_response;
  stale.direction = FrameDirection::in;
  stale.ack = AckPair{10'000, 1};
  stream.publish(SimTime{41'000}, stale);
  const auto verdicts = stream.judge(Invariant::no_stale_pair_after_reconnect);
  ASSERT_EQ(verdicts.size(), 1u);
  EXPECT_FALSE(verdicts[0].passed);
  EXPECT_NE(verdicts[0].actual.find("1 stale pair(s); first at 0.041s on truck-1"), std::string::npos) << verdicts[0].actual;
}

}  // namespace
}  // namespace ocp::scenario
