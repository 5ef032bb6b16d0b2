// The com channel's datagram codec (ocp/com_datagram.hpp): every LinkMessage round-trips, big
// ones in ≤ 1 200-byte pieces; hostile input (truncated, oversized, tampered, other key,
// replayed, reflected, random) is counted and dropped, never a crash.
#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "ocp/com_datagram.hpp"

namespace ocp::com {
namespace {

const ComKey key(32, 0x5a);
const ComKey other_key(32, 0xa5);

std::span<const std::uint8_t> bytes(const std::string& datagram) {
  return {reinterpret_cast<const std::uint8_t*>(datagram.data()), datagram.size()};
}

std::vector<std::string> seal(DatagramSealer& sealer, const LinkMessage& message) {
  std::vector<std::string> out;
  EXPECT_TRUE(sealer.seal(message, out));
  return out;
}

OperatorControl full_control() {
  OperatorControl control;
  control.sequence = 42;
  Controller controller;
  controller.buttons.a = controller.buttons.dpad_left = true;
  controller.axes.left_x = -0.25;
  controller.axes.right_trigger = 1.0;
  control.controller = controller;
  control.client_user_data = RawJson{R"({"mode":"auto","list":[1,2,3]})"};
  control.returned_ack = AckPair{0xfedcba9876543210ull, 0xdeadbeef};
  control.sender_faults = {FaultId::InputLost, FaultId::NoFeedbackMessage};
  return control;
}

StreamerFeedback full_feedback() {
  StreamerFeedback feedback;
  feedback.sequence = 7;
  feedback.receiver_faults = {FaultId::HighLatency};
  feedback.latency_ms = 35;
  feedback.missing_cameras = {"rear", "left"};
  feedback.vehicle_data = VehicleUserData{Position{57.7, 11.9}, RawJson{R"({"speed":3.5})"}};
  feedback.vehicle_data_age = Micros{12'000};
  feedback.last_remote_input = Controller::safe_default();
  return feedback;
}

template <typename T>
T round_trip(const T& message, bool to_streamer) {
  DatagramSealer sealer(key, 99);
  DatagramOpener opener(key, to_streamer);
  std::optional<LinkMessage> got;
  for (const auto& datagram : seal(sealer, message)) {
    EXPECT_LE(datagram.size(), max_datagram_bytes);
    auto opened = opener.open(bytes(datagram));
    EXPECT_EQ(opened.drop, Drop::none);
    if (opened.message) got = std::move(opened.message);
  }
  EXPECT_TRUE(got.has_value());
  return got ? std::get<T>(*got) : T{};
}

TEST(ComDatagram, EveryKindRoundTrips) {
  const auto control = round_trip(full_control(), true);
  EXPECT_EQ(control.sequence, 42u);
  EXPECT_EQ(control.controller, full_control().controller);
  EXPECT_EQ(control.client_user_data, full_control().client_user_data);
  EXPECT_EQ(control.returned_ack, full_control().returned_ack);
  EXPECT_EQ(control.sender_faults, full_control().sender_faults);

  const auto feedback = round_trip(full_feedback(), false);
  EXPECT_EQ(feedback.receiver_faults, full_feedback().receiver_faults);
  EXPECT_EQ(feedback.latency_ms, 35u);
  EXPECT_EQ(feedback.missing_cameras, full_feedback().missing_cameras);
  EXPECT_EQ(feedback.vehicle_data, full_feedback().vehicle_data);
  EXPECT_EQ(feedback.vehicle_data_age, Micros{12'000});
  EXPECT_EQ(feedback.last_remote_input, Controller::safe_default());

  const auto empty = round_trip(OperatorControl{}, true);
  EXPECT_FALSE(empty.controller || empty.client_user_data || empty.returned_ack);

  EXPECT_EQ(round_trip(Ping{5, SimTime{123}}, true).sent_at, SimTime{123});
  EXPECT_EQ(round_trip(Pong{5, SimTime{-7}}, false).ping_sent_at, SimTime{-7});
}

TEST(ComDatagram, VideoFrameIsCutIntoPiecesCarryingItsSize) {
  DatagramSealer sealer(key, 1);
  const VideoFrame frame{"front", 31, AckPair{111, 222}, 25'000};
  const auto datagrams = seal(sealer, frame);
  EXPECT_EQ(datagrams.size(), (25'000 + max_body_bytes - 1) / max_body_bytes);   // 23 pieces
  std::size_t total = 0;
  for (const auto& datagram : datagrams) {
    EXPECT_LE(datagram.size(), max_datagram_bytes);
    total += datagram.size() - header_bytes - tag_bytes;
  }
  EXPECT_EQ(total, 25'000u);
  // Reassembled in any order.
  DatagramOpener opener(key, false);
  std::optional<LinkMessage> got;
  for (auto it = datagrams.rbegin(); it != datagrams.rend(); ++it) {
    auto opened = opener.open(bytes(*it));
    if (opened.message) got = opened.message;
  }
  ASSERT_TRUE(got);
  const auto& received = std::get<VideoFrame>(*got);
  EXPECT_EQ(received.camera, "front");
  EXPECT_EQ(received.frame_number, 31u);
  EXPECT_EQ(received.sei, (AckPair{111, 222}));
  EXPECT_EQ(received.size_bytes, 25'000u);
}

TEST(ComDatagram, AFrameThatLostAPieceIsLostAndStateStaysBounded) {
  DatagramSealer sealer(key, 1);
  DatagramOpener opener(key, false);
  int delivered = 0;
  for (std::uint64_t n = 0; n < 100; ++n) {
    auto datagrams = seal(sealer, VideoFrame{"front", n, std::nullopt, 5'000});
    datagrams.erase(datagrams.begin() + 1);   // every frame loses its second piece
    for (const auto& datagram : datagrams) delivered += opener.open(bytes(datagram)).message ? 1 : 0;
  }
  EXPECT_EQ(delivered, 0);
  EXPECT_EQ(opener.counters().messages_lost, 100u - max_partial_messages);
  // Whole frames still get through after all that.
  for (const auto& datagram : seal(sealer, VideoFrame{"front", 200, std::nullopt, 5'000})) {
    delivered += opener.open(bytes(datagram)).message ? 1 : 0;
  }
  EXPECT_EQ(delivered, 1);
}

TEST(ComDatagram, ReplayedDatagramsAreDroppedOnce) {
  DatagramSealer sealer(key, 1);
  DatagramOpener opener(key, true);
  const auto first = seal(sealer, Ping{1, SimTime{0}});
  const auto second = seal(sealer, Ping{2, SimTime{0}});
  EXPECT_EQ(opener.open(bytes(second[0])).drop, Drop::none);
  EXPECT_EQ(opener.open(bytes(first[0])).drop, Drop::none);   // late, still in the window
  EXPECT_EQ(opener.open(bytes(first[0])).drop, Drop::replayed);
  EXPECT_EQ(opener.open(bytes(second[0])).drop, Drop::replayed);
  EXPECT_EQ(opener.counters().replayed, 2u);
}

TEST(ComDatagram, ReplayWindowForgetsWhatIsTooOld) {
  ReplayWindow window;
  EXPECT_FALSE(window.check_and_mark(0));
  EXPECT_TRUE(window.check_and_mark(1));
  EXPECT_TRUE(window.check_and_mark(1 + replay_window));
  EXPECT_FALSE(window.check_and_mark(1));                 // too old now
  EXPECT_TRUE(window.check_and_mark(2 + 0 + 1));          // inside the window, unseen
  EXPECT_FALSE(window.check_and_mark(3));
  EXPECT_TRUE(window.check_and_mark(100'000));            // a jump clears everything
  EXPECT_FALSE(window.check_and_mark(1 + replay_window));
}

TEST(ComDatagram, ARestartedPeerIsANewSessionAndAnOldRunCannotBeReplayed) {
  DatagramOpener opener(key, true);
  DatagramSealer first_run(key, 1);
  const auto old = seal(first_run, Ping{1, SimTime{0}});
  EXPECT_TRUE(opener.open(bytes(old[0])).new_session);
  DatagramSealer second_run(key, 2);   // sequence numbers start again at 1
  const auto fresh = seal(second_run, Ping{1, SimTime{0}});
  const auto opened = opener.open(bytes(fresh[0]));
  EXPECT_EQ(opened.drop, Drop::none);
  EXPECT_TRUE(opened.new_session);
  EXPECT_EQ(opener.open(bytes(old[0])).drop, Drop::replayed);   // the old run's window remembers
  EXPECT_EQ(opener.open(bytes(seal(second_run, Ping{2, SimTime{0}})[0])).drop, Drop::none);
  EXPECT_EQ(opener.counters().sessions, 2u);
}

TEST(ComDatagram, AnotherKeyOrATamperedByteIsABadMac) {
  DatagramSealer stranger(other_key, 1);
  DatagramOpener opener(key, true);
  EXPECT_EQ(opener.open(bytes(seal(stranger, Ping{1, SimTime{0}})[0])).drop, Drop::bad_mac);
  DatagramSealer sealer(key, 1);
  const auto good = seal(sealer, full_control())[0];
  for (std::size_t at = 0; at < good.size(); ++at) {
    std::string tampered = good;
    tampered[at] = static_cast<char>(tampered[at] ^ 0x01);
    EXPECT_NE(opener.open(bytes(tampered)).drop, Drop::none) << "byte " << at;
  }
  EXPECT_EQ(opener.open(bytes(good)).drop, Drop::none);   // none of them spent its sequence
  EXPECT_GE(opener.counters().bad_mac, good.size() - 32);
}

TEST(ComDatagram, TruncatedAndOversizedAreDropped) {
  DatagramSealer sealer(key, 1);
  DatagramOpener opener(key, true);
  const auto good = seal(sealer, full_control())[0];
  for (std::size_t length = 0; length < good.size(); ++length) {
    EXPECT_NE(opener.open(bytes(good.substr(0, length))).drop, Drop::none);
  }
  EXPECT_EQ(opener.open(bytes(good + "x")).drop, Drop::oversized);
  EXPECT_EQ(opener.open(bytes(std::string(max_datagram_bytes + 1, 'O'))).drop, Drop::oversized);
  EXPECT_EQ(opener.counters().messages, 0u);
}

TEST(ComDatagram, AReflectedDatagramIsTheWrongDirection) {
  DatagramSealer player(key, 1);
  DatagramOpener player_side(key, false);   // the Player accepts only what a Streamer sends
  EXPECT_EQ(player_side.open(bytes(seal(player, Ping{1, SimTime{0}})[0])).drop, Drop::wrong_direction);
}

TEST(ComDatagram, MalformedBodiesAreRefused) {
  EXPECT_FALSE(decode_body(LinkKind::ping, ""));
  EXPECT_FALSE(decode_body(LinkKind::ping, std::string(17, '\0')));   // one byte too many
  EXPECT_FALSE(decode_body(static_cast<LinkKind>(9), std::string(16, '\0')));
  OperatorControl control = full_control();
  std::string body = encode_body(control);
  EXPECT_TRUE(decode_body(LinkKind::operator_control, body));
  EXPECT_FALSE(decode_body(LinkKind::operator_control, body.substr(0, body.size() - 1)));
  control.client_user_data = RawJson{"{not json"};
  EXPECT_FALSE(decode_body(LinkKind::operator_control, encode_body(control)));
  control = full_control();
  control.controller->axes.left_x = 2.0;   // outside [-1, 1]
  EXPECT_FALSE(decode_body(LinkKind::operator_control, encode_body(control)));
  control.controller->axes.left_x = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(decode_body(LinkKind::operator_control, encode_body(control)));
  StreamerFeedback feedback;
  body = encode_body(feedback);
  body[8] = 1;          // one fault …
  body.insert(9, 1, static_cast<char>(fault_count));   // … that does not exist
  EXPECT_FALSE(decode_body(LinkKind::streamer_feedback, body));
}

TEST(ComDatagram, RandomAndMutatedInputNeverCrashes) {
  std::mt19937_64 random(2024);
  DatagramSealer sealer(key, 1);
  DatagramOpener opener(key, true);
  const auto good = seal(sealer, full_control())[0];
  ASSERT_EQ(opener.open(bytes(good)).drop, Drop::none);   // a mutation that undoes itself is a replay
  for (int i = 0; i < 20'000; ++i) {
    std::string junk = i % 2 ? good : std::string(random() % 1300, '\0');
    for (std::size_t flips = 0; flips < 1 + random() % 8 && !junk.empty(); ++flips) {
      junk[random() % junk.size()] ^= static_cast<char>(1 + random() % 255);
    }
    (void)opener.open(bytes(junk));
    (void)decode_body(static_cast<LinkKind>(1 + random() % 5), junk);
  }
  EXPECT_EQ(opener.counters().messages, 1u);
  EXPECT_EQ(opener.counters().dropped(), 20'000u);
}

TEST(ComDatagram, InsecureModeUsesOneCodePathWithAnEmptyKey) {
  DatagramSealer sealer({}, 1);
  DatagramOpener opener({}, true);
  EXPECT_EQ(opener.open(bytes(seal(sealer, Ping{1, SimTime{0}})[0])).drop, Drop::none);
  DatagramOpener keyed(key, true);
  EXPECT_EQ(keyed.open(bytes(seal(sealer, Ping{2, SimTime{0}})[0])).drop, Drop::bad_mac);
}

}  // namespace
}  // namespace ocp::com
