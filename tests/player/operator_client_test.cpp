// The operator TCP client (`tcp` source) over an in-memory pipe: VehicleOcpShared out each
// frame, ClientOcpShared in, one client at a time, and every SPEC §2 rule for bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>

#include "player_harness.hpp"

namespace ocp::testing {
namespace {

constexpr AckPair pair{9'007'199'254'740'993ULL, 4'000'000'001U};

ClientOcpShared echo_message(std::optional<std::string> user_data = std::nullopt) {
  ClientVehicleEntry entry;
  entry.ack_time_returned = pair.ack_time;
  entry.ack_time_mac_returned = pair.ack_time_mac;
  if (user_data) entry.user_data = RawJson{*user_data};
  return client_entry("truck-1", entry);
}

class PlayerTcpClient : public ::testing::Test {
 protected:
  PlayerTcpClient() {
    EXPECT_TRUE(harness.add_vehicle("truck-1").ok());
    harness.player.start();
  }
  PlayerHarness harness;
};

TEST_F(PlayerTcpClient, ReceivesTheSharedObjectEveryFrame) {
  TestOperatorClient client(harness);
  harness.video_at(at_ms(3), "truck-1", pair);
  harness.run_until(at_ms(95));
  ASSERT_EQ(client.received.size(), 10u);  // frames 0 … 90 ms
  EXPECT_EQ(client.received_at[9], at_ms(90));
  EXPECT_EQ(client.received.back(), harness.player.last_shared());
  EXPECT_EQ(client.received.back().vehicle_feedback.at("truck-1").ack, pair);  // byte-exact
  EXPECT_TRUE(harness.player.client_connected());
  EXPECT_EQ(client.decode_errors, 0u);
}

TEST_F(PlayerTcpClient, ItsEchoAndUserDataReachTheVehicle) {
  TestOperatorClient client(harness);
  harness.executor.call_at(at_ms(15), [&] { client.send(echo_message(R"({"tool":"bucket"})")); });
  harness.run_until(at_ms(20));
  EXPECT_EQ(harness.player.locked_source(), ClientSource::tcp);
  const auto control = harness.control_at("truck-1", at_ms(20));
  ASSERT_TRUE(control.has_value());
  EXPECT_EQ(control->returned_ack, pair);
  EXPECT_EQ(control->client_user_data, RawJson{R"({"tool":"bucket"})"});
}

TEST_F(PlayerTcpClient, SecondClientIsClosedAtOnceAndTheFirstKeepsWorking) {
  TestOperatorClient first(harness, "pipe:first");
  harness.run_until(at_ms(5));
  TestOperatorClient second(harness, "pipe:second");
  harness.run_until(at_ms(30));
  EXPECT_TRUE(second.closed_by_peer());
  EXPECT_EQ(second.closed_at(), at_ms(5));
  EXPECT_TRUE(second.received.empty());
  EXPECT_FALSE(first.closed_by_peer());
  EXPECT_EQ(first.received.size(), 4u);
  const CapturedLog::Line* refusal = harness.find_log(LogLevel::warn, "refused");
  ASSERT_NE(refusal, nullptr);
  EXPECT_NE(refusal->message.find("pipe:first"), std::string::npos);
  EXPECT_NE(refusal->message.find("pipe:second"), std::string::npos);
  EXPECT_EQ(harness.player.stats().client_connections_refused, 1u);
}

TEST_F(PlayerTcpClient, NewClientAcceptedAfterThePreviousLeft) {
  auto first = std::make_unique<TestOperatorClient>(harness, "pipe:first");
  harness.run_until(at_ms(5));
  first->close();
  harness.run_until(at_ms(6));
  EXPECT_FALSE(harness.player.client_connected());
  TestOperatorClient second(harness, "pipe:second");
  harness.run_until(at_ms(20));
  EXPECT_FALSE(second.closed_by_peer());
  EXPECT_EQ(second.received.size(), 2u);
}

// SPEC §4.3 Decision: the lock stays with the tcp source when its client leaves. Told once
// (not per connection, which a storm would flood) until a tcp client sends client data again.
TEST_F(PlayerTcpClient, LockedClientLeavingIsToldOnceUntilATcpClientTakesOver) {
  const auto told = [&] {
    return std::count_if(harness.log.lines().begin(), harness.log.lines().end(), [](const CapturedLog::Line& line) {
      return line.level == LogLevel::warn && line.message.find(tcp_lock_without_client_text) != std::string::npos;
    });
  };
  auto first = std::make_unique<TestOperatorClient>(harness, "pipe:first");
  harness.executor.call_at(at_ms(5), [&] { first->send(echo_message()); });
  harness.run_until(at_ms(10));
  EXPECT_FALSE(harness.player.tcp_lock_without_client());
  first->close();
  harness.run_until(at_ms(20));
  EXPECT_TRUE(harness.player.tcp_lock_without_client());
  EXPECT_EQ(harness.player.locked_source(), ClientSource::tcp);
  EXPECT_EQ(told(), 1);
  // A client that connects and leaves without sending client data changes nothing.
  auto idle = std::make_unique<TestOperatorClient>(harness, "pipe:idle");
  harness.run_until(at_ms(30));
  EXPECT_FALSE(harness.player.tcp_lock_without_client());
  idle->close();
  harness.run_until(at_ms(40));
  EXPECT_TRUE(harness.player.tcp_lock_without_client());
  EXPECT_EQ(told(), 1);
  // One that takes over and leaves is told again (a second later: the line goes with the
  // disconnect line, within the connection log budget of two a second).
  harness.run_until(at_ms(1100));
  auto second = std::make_unique<TestOperatorClient>(harness, "pipe:second");
  harness.executor.call_at(at_ms(1105), [&] { second->send(echo_message()); });
  harness.run_until(at_ms(1110));
  second->close();
  harness.run_until(at_ms(1120));
  EXPECT_EQ(told(), 2);
}

// SPEC §4.3 Decision: "source tcp locked, no client connected: no pair is returned". The
// departed client's last pair must not be returned for it (issue #35: the Streamer would show
// a growing latency instead of InvalidMac).
TEST_F(PlayerTcpClient, LockedClientLeavingReturnsNoPairUntilATcpClientTakesOver) {
  auto first = std::make_unique<TestOperatorClient>(harness, "pipe:first");
  harness.executor.call_at(at_ms(5), [&] { first->send(echo_message(R"({"tool":"bucket"})")); });
  harness.run_until(at_ms(20));
  ASSERT_EQ(harness.control_at("truck-1", at_ms(20))->returned_ack, pair);
  harness.executor.call_at(at_ms(25), [&] { first->close(); });
  harness.run_until(at_ms(30));
  const auto after_leave = harness.control_at("truck-1", at_ms(30));
  ASSERT_TRUE(after_leave.has_value());
  EXPECT_FALSE(after_leave->returned_ack.has_value());
  EXPECT_EQ(harness.player.locked_source(), ClientSource::tcp);
  // A new tcp client takes over and its pair is returned again.
  TestOperatorClient second(harness, "pipe:second");
  harness.executor.call_at(at_ms(35), [&] { second.send(echo_message()); });
  harness.run_until(at_ms(40));
  EXPECT_EQ(harness.control_at("truck-1", at_ms(40))->returned_ack, pair);
}

TEST_F(PlayerTcpClient, SilenceClosesAfterExactlyTheReadTimeout) {
  TestOperatorClient client(harness);
  harness.executor.call_at(at_ms(500), [&] { client.send(echo_message()); });
  harness.run_until(SimTime{2'499'999});
  EXPECT_FALSE(client.closed_by_peer());
  harness.run_until(SimTime{2'500'000});
  EXPECT_TRUE(client.closed_by_peer());
  EXPECT_EQ(client.closed_at(), SimTime{2'500'000});
  ASSERT_TRUE(harness.player.last_client_close_reason().has_value());
  EXPECT_EQ(harness.player.last_client_close_reason()->code, PeerError::read_timeout);
}

TEST_F(PlayerTcpClient, MalformedJsonClosesWithReason) {
  TestOperatorClient client(harness);
  harness.executor.call_at(at_ms(7), [&] { client.send_payload("{\"active_vehicle\": "); });
  harness.run_until(at_ms(20));
  EXPECT_TRUE(client.closed_by_peer());
  EXPECT_EQ(client.closed_at(), at_ms(7));
  EXPECT_FALSE(harness.player.client_connected());
  ASSERT_TRUE(harness.player.last_client_close_reason().has_value());
  EXPECT_EQ(harness.player.last_client_close_reason()->code, PeerError::malformed_json);
  EXPECT_TRUE(harness.logged(LogLevel::warn, "closing tcp client"));
  EXPECT_EQ(harness.player.locked_source(), std::nullopt);  // nothing was applied
}

TEST_F(PlayerTcpClient, WrongTypesAndNonObjectsClose) {
  for (const char* payload : {R"({"active_vehicle": 5})", "[1, 2, 3]", "42",
                              R"({"client_user_data": {"truck-1": {"ack_time_returned": -1}}})",
                              R"({"client_user_data": {"truck-1": {"ack_time_mac_returned": 4294967296}}})"}) {
    TestOperatorClient client(harness, std::string("pipe:") + payload);
    client.send_payload(payload);
    harness.run_until(harness.executor.now() + Micros{1});
    EXPECT_TRUE(client.closed_by_peer()) << payload;
  }
  EXPECT_EQ(harness.player.stats().client_messages_received, 0u);
}

TEST_F(PlayerTcpClient, UnknownFieldsAreIgnored) {
  TestOperatorClient client(harness);
  client.send_payload(R"({"future": [1, {"x": null}], "client_user_data": {"truck-1":
      {"ack_time_returned": 9007199254740993, "ack_time_mac_returned": 4000000001, "extra": true}}})");
  harness.run_until(at_ms(10));
  EXPECT_FALSE(client.closed_by_peer());
  EXPECT_EQ(harness.control_at("truck-1", at_ms(10))->returned_ack, pair);
}

TEST_F(PlayerTcpClient, OversizedFrameIsDrainedAndTheConnectionKept) {
  TestOperatorClient client(harness);
  const std::string huge(20'000, 'x');
  harness.executor.call_at(at_ms(3), [&] {
    client.send_payload(huge);
    client.send(echo_message());
  });
  harness.run_until(at_ms(10));
  EXPECT_FALSE(client.closed_by_peer());
  EXPECT_EQ(harness.player.stats().client_oversized_frames, 1u);
  EXPECT_TRUE(harness.logged(LogLevel::warn, "oversized"));
  EXPECT_EQ(harness.control_at("truck-1", at_ms(10))->returned_ack, pair);
}

TEST_F(PlayerTcpClient, EndOfStreamInsideAFrameIsReportedAsTruncated) {
  TestOperatorClient client(harness);
  harness.executor.call_at(at_ms(3), [&] {
    client.send_raw(length_prefix(100) + R"({"active_v)");
    client.close();
  });
  harness.run_until(at_ms(10));
  EXPECT_FALSE(harness.player.client_connected());
  ASSERT_TRUE(harness.player.last_client_close_reason().has_value());
  EXPECT_EQ(harness.player.last_client_close_reason()->code, PeerError::truncated_frame);
  EXPECT_TRUE(harness.logged(LogLevel::warn, "inside a frame"));
}

TEST_F(PlayerTcpClient, HostileLengthHeaderDoesNotStallAndTimesOut) {
  TestOperatorClient client(harness);
  harness.executor.call_at(at_ms(1), [&] { client.send_raw(length_prefix(0xffffffffU) + "abc"); });
  harness.run_until(at_ms(1000));
  EXPECT_FALSE(client.closed_by_peer());  // still draining: the bytes may yet arrive
  EXPECT_EQ(harness.controls("truck-1").size(), 101u);
  harness.run_until(at_ms(2001));
  EXPECT_TRUE(client.closed_by_peer());
  EXPECT_EQ(client.closed_at(), at_ms(2001));
}

TEST_F(PlayerTcpClient, FloodOfFramesIsAllDecodedLatestWins) {
  TestOperatorClient client(harness);
  harness.executor.call_at(at_ms(3), [&] {
    std::string burst;
    for (int index = 0; index < 10'000; ++index) {
      ClientOcpShared message = echo_message("{\"n\":" + std::to_string(index) + "}");
      std::string json;
      encode_client_ocp_shared(message, json);
      burst += frame_of(json);
    }
    client.send_raw(burst);
  });
  harness.run_until(SimTime{999'999});
  EXPECT_FALSE(client.closed_by_peer());
  EXPECT_EQ(harness.player.stats().client_messages_received, 10'000u);
  EXPECT_EQ(harness.controls("truck-1").size(), 100u);  // the frame loop did not slip
  EXPECT_EQ(harness.control_at("truck-1", at_ms(10))->client_user_data, RawJson{R"({"n":9999})"});
}

TEST_F(PlayerTcpClient, BytesArrivingOneAtATimeDecodeTheSame) {
  TestOperatorClient client(harness, "pipe:slow", /*max_chunk_bytes=*/1);
  harness.executor.call_at(at_ms(3), [&] { client.send(echo_message(R"({"a":[1,2,3]})")); });
  harness.run_until(at_ms(10));
  EXPECT_FALSE(client.closed_by_peer());
  EXPECT_EQ(harness.control_at("truck-1", at_ms(10))->client_user_data, RawJson{R"({"a":[1,2,3]})"});
  EXPECT_EQ(client.received.size(), 2u);
}

TEST_F(PlayerTcpClient, OversizedOutboundObjectIsNeverSent) {
  TestOperatorClient client(harness);
  StreamerFeedback feedback;
  VehicleUserData data;
  data.user_data = RawJson{"\"" + std::string(17'000, 'z') + "\""};
  feedback.vehicle_data = data;
  harness.deliver_at(at_ms(15), "truck-1", LinkMessage{feedback});
  harness.run_until(at_ms(50));
  EXPECT_EQ(client.received.size(), 2u);  // frames 0 and 10 ms only
  EXPECT_FALSE(client.closed_by_peer());
  EXPECT_EQ(harness.player.stats().client_frames_too_large, 4u);  // 20 … 50 ms
  int warnings = 0;
  for (const CapturedLog::Line& log : harness.log.lines()) warnings += log.message.find("not sent") != std::string::npos;
  EXPECT_EQ(warnings, 1);
}

TEST_F(PlayerTcpClient, StopClosesTheClient) {
  TestOperatorClient client(harness);
  harness.run_until(at_ms(10));
  harness.player.stop();
  harness.run_until(at_ms(11));
  EXPECT_TRUE(client.closed_by_peer());
  EXPECT_EQ(harness.player.last_client_close_reason(), (CloseReason{LocalError::shut_down, "player stopped"}));
}

}  // namespace
}  // namespace ocp::testing
