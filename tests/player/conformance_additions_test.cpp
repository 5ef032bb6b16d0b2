// The PlayerCore additions the `ocp_conformance operator` suite uses (player_core.hpp,
// "Conformance testing"), in virtual time over a pipe: paused client output, server close,
// raw frames (cut in pieces, coalesced, oversized).
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "ocp/json_codec.hpp"

#include "player_harness.hpp"

namespace ocp::testing {
namespace {

class PlayerConformanceAdditions : public ::testing::Test {
 protected:
  PlayerConformanceAdditions() {
    EXPECT_TRUE(harness.add_vehicle("truck-1").ok());
    harness.player.start();
  }
  PlayerHarness harness;
};

TEST_F(PlayerConformanceAdditions, PausedClientOutputWritesNothingButFramesGoOn) {
  TestOperatorClient client(harness);
  harness.run_until(at_ms(100));
  const std::size_t before = client.received.size();
  EXPECT_GE(before, 9u);
  harness.player.set_client_output_paused(true);
  EXPECT_TRUE(harness.player.client_output_paused());
  const std::size_t controls = harness.controls("truck-1").size();
  harness.run_until(at_ms(600));
  EXPECT_EQ(client.received.size(), before);
  EXPECT_GE(harness.controls("truck-1").size(), controls + 49);   // the vehicle still gets control
  harness.player.set_client_output_paused(false);
  harness.run_until(at_ms(650));
  EXPECT_GT(client.received.size(), before);
}

TEST_F(PlayerConformanceAdditions, PausedOutputLetsTheReadTimeoutFireOnASilentClient) {
  TestOperatorClient client(harness);
  harness.player.set_client_output_paused(true);
  harness.run_until(at_ms(2'100));
  EXPECT_TRUE(client.closed_by_peer());
  ASSERT_TRUE(harness.player.last_client_close_reason().has_value());
  EXPECT_EQ(harness.player.last_client_close_reason()->code, PeerError::read_timeout);
}

TEST_F(PlayerConformanceAdditions, CloseClientConnectionClosesFromTheServerSide) {
  TestOperatorClient client(harness);
  harness.run_until(at_ms(50));
  ASSERT_TRUE(harness.player.client_connected());
  harness.player.close_client_connection();
  harness.run_until(at_ms(60));
  EXPECT_FALSE(harness.player.client_connected());
  EXPECT_TRUE(client.closed_by_peer());
  ASSERT_TRUE(harness.player.last_client_close_reason().has_value());
  EXPECT_EQ(harness.player.last_client_close_reason()->code, LocalError::shut_down);
  harness.player.close_client_connection();   // no client: no-op
  // The next client is accepted (nothing left of the closed one).
  TestOperatorClient next(harness, "pipe:operator-2");
  harness.run_until(at_ms(100));
  EXPECT_TRUE(harness.player.client_connected());
  EXPECT_FALSE(next.received.empty());
}

// A VehicleOcpShared frame (prefix + payload) carrying `pair` for truck-1.
std::string shared_frame(const AckPair& pair) {
  VehicleOcpShared shared;
  shared.vehicle_feedback["truck-1"].ack = pair;
  std::string json;
  encode_vehicle_ocp_shared(shared, json);
  return frame_of(json);
}

TEST_F(PlayerConformanceAdditions, RawFrameInPiecesArrivesWholeAfterTheLastPiece) {
  TestOperatorClient client(harness);
  harness.player.set_client_output_paused(true);
  harness.run_until(at_ms(5));
  const std::size_t before = client.received.size();
  const AckPair pair{~std::uint64_t{0}, 0xFFFFFFFFu};
  const std::string frame = shared_frame(pair);
  std::vector<std::uint32_t> published;
  auto subscription = harness.player.events().subscribe([&](const Event& event) {
    if (const auto* wire = std::get_if<WireFrame>(&event.body); wire && wire->direction == FrameDirection::out) {
      published.push_back(wire->length_prefix);
    }
  });
  const std::uint64_t bytes_before = harness.player.stats().client_bytes_out;
  ASSERT_TRUE(harness.player.write_raw_to_client(frame, {1, 4, 10}, Micros{2000}).ok());
  EXPECT_EQ(harness.player.stats().client_bytes_out - bytes_before, 1u);   // the first piece only
  EXPECT_EQ(published, std::vector<std::uint32_t>{static_cast<std::uint32_t>(frame.size() - 4)});
  harness.run_until(at_ms(5) + Micros{5'900});
  EXPECT_EQ(client.received.size(), before);   // last piece due at +6 ms
  EXPECT_EQ(harness.player.stats().client_bytes_out - bytes_before, 10u);
  harness.run_until(at_ms(12));
  EXPECT_EQ(harness.player.stats().client_bytes_out - bytes_before, frame.size());
  ASSERT_EQ(client.received.size(), before + 1);
  EXPECT_EQ(client.latest().vehicle_feedback.at("truck-1").ack, pair);
  EXPECT_GE(client.received_at.back() - at_ms(5), Micros{6000});
}

TEST_F(PlayerConformanceAdditions, CoalescedRawFramesArriveAsSeveralAndEachIsPublished) {
  TestOperatorClient client(harness);
  harness.player.set_client_output_paused(true);
  harness.run_until(at_ms(5));
  const std::size_t before = client.received.size();
  std::size_t published = 0;
  auto subscription = harness.player.events().subscribe([&](const Event& event) {
    if (const auto* wire = std::get_if<WireFrame>(&event.body); wire && wire->direction == FrameDirection::out) ++published;
  });
  std::string bytes;
  for (std::uint32_t i = 0; i < 5; ++i) bytes += shared_frame(AckPair{100 + i, i});
  ASSERT_TRUE(harness.player.write_raw_to_client(bytes).ok());
  EXPECT_EQ(published, 5u);
  harness.run_until(at_ms(10));
  ASSERT_EQ(client.received.size(), before + 5);
  EXPECT_EQ(client.latest().vehicle_feedback.at("truck-1").ack, (AckPair{104, 4}));
}

TEST_F(PlayerConformanceAdditions, OversizedRawFrameIsWrittenAsIsAndDrainedByTheClient) {
  TestOperatorClient client(harness);
  harness.player.set_client_output_paused(true);
  harness.run_until(at_ms(5));
  const std::string bytes = length_prefix(20000) + std::string(20000, 'x');
  ASSERT_TRUE(harness.player.write_raw_to_client(bytes + shared_frame(AckPair{7, 7})).ok());
  harness.run_until(at_ms(10));
  EXPECT_EQ(client.oversized_lengths(), std::vector<std::uint32_t>{20000});
  EXPECT_EQ(client.latest().vehicle_feedback.at("truck-1").ack, (AckPair{7, 7}));
  EXPECT_TRUE(harness.player.client_connected());
}

TEST_F(PlayerConformanceAdditions, RawWriteWithoutClientFailsAndLatePiecesAreDropped) {
  const Status none = harness.player.write_raw_to_client("abcd");
  ASSERT_FALSE(none.ok());
  EXPECT_EQ(none.error().code, make_error_code(LocalError::not_connected));
  TestOperatorClient client(harness);
  harness.player.set_client_output_paused(true);
  harness.run_until(at_ms(5));
  const std::size_t before = client.received.size();
  ASSERT_TRUE(harness.player.write_raw_to_client(shared_frame(AckPair{1, 1}), {6}, Micros{5000}).ok());
  harness.player.close_client_connection();
  TestOperatorClient next(harness, "pipe:operator-2");
  harness.run_until(at_ms(20));
  EXPECT_EQ(client.received.size(), before);   // its second piece never came
  EXPECT_TRUE(next.received.empty());           // and did not go to the next client either
  EXPECT_EQ(next.decode_errors, 0u);
}

}  // namespace
}  // namespace ocp::testing
