// Each --misbehave switch produces its wire effect (what makes the Streamer raise its fault).
#include <gtest/gtest.h>

#include "world.hpp"

namespace ocp {
namespace {

using testing::ClientWorld;
using testing::ms;

VehicleClientConfig misbehaving(void (*set)(Misbehaviour&)) {
  VehicleClientConfig config;
  set(config.misbehave);
  return config;
}

TEST(VehicleClientMisbehaviour, AllSwitchesAreOffByDefault) {
  const Misbehaviour misbehave;
  EXPECT_FALSE(misbehave.any());
  EXPECT_EQ(misbehave.describe(), "none");
}

TEST(VehicleClientMisbehaviour, StopEchoKeepsSendingTheFirstPair) {
  ClientWorld world(misbehaving([](Misbehaviour& m) { m.stop_echo = true; }));
  world.streamer->start_control_loop();
  world.executor.run_for(ms(200));
  const AckPair first = world.streamer->sent.front().ack;
  ASSERT_GT(world.streamer->sent.size(), 10u);
  ASSERT_FALSE(world.streamer->responses.empty());
  for (const auto& response : world.streamer->responses) EXPECT_EQ(response.message.ack, first);
}

TEST(VehicleClientMisbehaviour, CorruptMacSendsAMacThatFailsVerification) {
  ClientWorld world(misbehaving([](Misbehaviour& m) { m.corrupt_mac = true; }));
  world.streamer->start_control_loop();
  world.executor.run_for(ms(100));
  ASSERT_FALSE(world.streamer->responses.empty());
  for (const auto& response : world.streamer->responses) {
    EXPECT_FALSE(world.streamer->verify(response.message.ack));
  }
  const auto& echoed = world.streamer->responses.front().message.ack;
  const auto& sent = world.streamer->sent.front().ack;
  EXPECT_EQ(echoed.ack_time, sent.ack_time);
  EXPECT_EQ(echoed.ack_time_mac, sent.ack_time_mac ^ corrupt_mac_mask);
}

TEST(VehicleClientMisbehaviour, AckThroughDoubleBreaksAckTimesAboveTwoToThe53) {
  ClientWorld world(misbehaving([](Misbehaviour& m) { m.ack_through_double = true; }));
  OcpControlMessage message;
  message.ack = world.streamer->issue((1ull << 53) - 1);  // still exact in a double
  world.streamer->send_control(message, /*keep_pair=*/true);
  world.executor.run_for(ms(1));
  EXPECT_EQ(world.streamer->responses.back().message.ack.ack_time, (1ull << 53) - 1);

  message.ack = world.streamer->issue((1ull << 53) + 1);  // the conformance value
  world.streamer->send_control(message, /*keep_pair=*/true);
  world.executor.run_for(ms(1));
  const AckPair echoed = world.streamer->responses.back().message.ack;
  EXPECT_EQ(echoed.ack_time, 1ull << 53);
  EXPECT_FALSE(world.streamer->verify(echoed));
}

TEST(VehicleClientMisbehaviour, OversizedFramesExceedTheLimitAndAreDrained) {
  ClientWorld world(misbehaving([](Misbehaviour& m) { m.oversized_frames = true; }));
  world.streamer->start_control_loop();
  world.executor.run_for(ms(50));
  EXPECT_TRUE(world.streamer->responses.empty());
  ASSERT_FALSE(world.streamer->oversized_lengths().empty());
  for (std::uint32_t length : world.streamer->oversized_lengths()) EXPECT_GE(length, 16385u);
}

TEST(VehicleClientMisbehaviour, DelayResponsesSendsEveryResponseLate) {
  ClientWorld world(misbehaving([](Misbehaviour& m) { m.delay_responses = Micros{50'000}; }));
  world.streamer->send_control(OcpControlMessage{});
  const SimTime sent_at = world.executor.now();
  world.executor.run_until(sent_at + ms(50) - Micros{1});
  EXPECT_TRUE(world.streamer->responses.empty());
  world.executor.run_until(sent_at + ms(50));
  ASSERT_EQ(world.streamer->responses.size(), 1u);
  EXPECT_EQ(world.streamer->responses[0].message.ack, world.streamer->sent[0].ack);
}

TEST(VehicleClientMisbehaviour, MalformedJsonSendsFramesThatAreNotJson) {
  ClientWorld world(misbehaving([](Misbehaviour& m) { m.malformed_json = true; }));
  world.streamer->start_control_loop();
  world.executor.run_for(ms(50));
  EXPECT_TRUE(world.streamer->responses.empty());
  EXPECT_FALSE(world.streamer->decode_errors.empty());
}

TEST(VehicleClientMisbehaviour, SilentNeverSendsAByte) {
  ClientWorld world(misbehaving([](Misbehaviour& m) { m.silent = true; }));
  world.streamer->start_control_loop();
  world.executor.run_for(ms(1000));
  EXPECT_EQ(world.streamer->bytes_received(), 0u);
  EXPECT_GT(world.client->stats().control_messages_received, 90u);
}

TEST(VehicleClientMisbehaviour, UserDataSaysTheClientIsMisbehaving) {
  ClientWorld world(misbehaving([](Misbehaviour& m) { m.corrupt_mac = true; m.stop_echo = true; }));
  world.executor.run_for(ms(20));
  EXPECT_NE(world.client->user_data_json().find(R"("misbehave":"stop-echo, corrupt-mac")"), std::string::npos)
      << world.client->user_data_json();
}

}  // namespace
}  // namespace ocp

namespace ocp {
namespace {

TEST(VehicleClientMisbehaviour, BadResponseNamesRoundTrip) {
  for (BadResponse kind : {BadResponse::none, BadResponse::missing_field, BadResponse::wrong_type, BadResponse::not_an_object,
                           BadResponse::ack_time_out_of_range, BadResponse::eof_mid_frame}) {
    EXPECT_EQ(parse_bad_response(bad_response_name(kind)), kind) << bad_response_name(kind);
  }
  EXPECT_EQ(parse_bad_response("ack_time_out_of_range"), BadResponse::ack_time_out_of_range);
  EXPECT_EQ(parse_bad_response("missing"), std::nullopt);
  Misbehaviour misbehave;
  misbehave.bad_response = BadResponse::wrong_type;
  EXPECT_TRUE(misbehave.any());
  EXPECT_EQ(misbehave.describe(), "bad-response wrong-type");
}

// Every broken response is one the codec refuses: the Streamer can only close (SPEC §2).
TEST(VehicleClientMisbehaviour, BadResponsesAreRefusedByTheCodec) {
  for (BadResponse kind : {BadResponse::missing_field, BadResponse::wrong_type, BadResponse::not_an_object,
                           BadResponse::ack_time_out_of_range}) {
    VehicleClientConfig config;
    config.misbehave.bad_response = kind;
    ClientWorld world(config);
    world.streamer->start_control_loop();
    world.executor.run_for(ms(50));
    EXPECT_TRUE(world.streamer->responses.empty()) << bad_response_name(kind);
    EXPECT_FALSE(world.streamer->decode_errors.empty()) << bad_response_name(kind);
  }
}

TEST(VehicleClientMisbehaviour, EofMidFrameHangsUpAfterHalfAFrame) {
  VehicleClientConfig config;
  config.misbehave.bad_response = BadResponse::eof_mid_frame;
  ClientWorld world(config);
  world.streamer->start_control_loop();
  world.executor.run_for(ms(50));
  EXPECT_TRUE(world.streamer->responses.empty());
  EXPECT_GT(world.streamer->bytes_received(), 0u);
  EXPECT_EQ(world.client->stats().last_disconnect_kind, DisconnectKind::misbehaved);
}

}  // namespace
}  // namespace ocp
