// Hostile bytes on the vehicle-side stream (issue #3 "Bad input"): every case is handled as
// SPEC §2 says, and none of them stalls or slows the world — the control cadence to the
// remaining (or next) connection stays exactly 10 ms.
#include <gtest/gtest.h>
#include <time.h>

#include <chrono>

#include "world_fixture.hpp"

namespace ocp::world_test {
namespace {

// CPU seconds this thread has used: unlike wall time, not inflated by a loaded machine.
double thread_cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + static_cast<double>(now.tv_nsec) / 1e9;
}

WorldConfig raw_vehicle_config() {
  WorldConfig config = one_vehicle_config();
  config.vehicles[0].in_process_client = false;
  return config;
}

class WorldBadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(sim.start());
    sim.run_until(SimTime{Millis{95}});
    peer = connect_vehicle_peer(sim, "truck-1");
    sim.run_for(Millis{100});
    ASSERT_TRUE(streamer().vehicle_connected());
  }
  StreamerCore& streamer() { return sim.world().streamer("truck-1"); }

  // The connection is closed (by the Streamer, with a reason naming the problem), and a new
  // well-behaved connection afterwards gets control frames every 10 ms exactly.
  // `detail_part`: what the detail must say (the field, or where the JSON broke), beside the
  // typed code.
  void expect_closed_then_next_connection_is_served(PeerError code, const std::string& detail_part) {
    ASSERT_FALSE(detail_part.empty()) << "an empty part is found in any detail";
    sim.run_for(Millis{10});
    EXPECT_TRUE(peer->closed_by_peer());
    EXPECT_FALSE(streamer().vehicle_connected());
    const auto& reason = streamer().stats().last_close_reason;
    ASSERT_TRUE(reason.has_value());
    EXPECT_EQ(reason->code, code) << reason->message();
    EXPECT_NE(reason->detail.find(detail_part), std::string::npos) << reason->message();
    auto next = connect_vehicle_peer(sim, "truck-1");
    next->echo = true;
    sim.run_for(Millis{500});
    EXPECT_TRUE(streamer().vehicle_connected());
    EXPECT_EQ(next->received_at.size(), 50u);
    EXPECT_TRUE(cadence_exact(next->received_at));
    EXPECT_GT(streamer().stats().vehicle_responses_received, 40u);
  }

  VirtualWorld sim{raw_vehicle_config()};
  std::unique_ptr<testing::VehiclePeer> peer;
};

TEST_F(WorldBadInput, MalformedJsonClosesTheConnection) {
  peer->send_payload(R"({"ack_time": 1, "ack_time_mac": )");
  expect_closed_then_next_connection_is_served(PeerError::malformed_json, "Invalid value. (offset 32)");
}

TEST_F(WorldBadInput, NonObjectJsonClosesTheConnection) {
  peer->send_payload("[1, 2, 3]");
  expect_closed_then_next_connection_is_served(PeerError::not_an_object, "top-level value is not an object");
}

TEST_F(WorldBadInput, MissingRequiredFieldClosesTheConnection) {
  peer->send_payload(R"({"ack_time_mac": 5})");
  expect_closed_then_next_connection_is_served(PeerError::missing_field, "ack_time");
}

TEST_F(WorldBadInput, WrongTypeClosesTheConnection) {
  peer->send_payload(R"({"ack_time": "123", "ack_time_mac": 5})");
  expect_closed_then_next_connection_is_served(PeerError::wrong_type, "ack_time");
}

TEST_F(WorldBadInput, OutOfRangeIntegersCloseTheConnection) {
  peer->send_payload(R"({"ack_time": 1, "ack_time_mac": 4294967296})");
  expect_closed_then_next_connection_is_served(PeerError::out_of_range, "ack_time_mac");
}

TEST_F(WorldBadInput, DeeplyNestedUserDataClosesTheConnection) {
  std::string nested = R"({"ack_time": 1, "ack_time_mac": 2, "vehicle_user_data": {"user_data": )";
  nested.append(5000, '[');
  nested.append(5000, ']');
  nested += "}}";
  peer->send_payload(nested);
  sim.run_for(Millis{10});
  EXPECT_TRUE(peer->closed_by_peer());
  expect_closed_then_next_connection_is_served(PeerError::too_deep, "nesting deeper than 64 levels at offset 133");
}

TEST_F(WorldBadInput, StreamEndingInsideAFrameIsATruncatedFrame) {
  peer->send_raw(testing::length_prefix(100) + "{\"ack_time\"");
  peer->close();
  sim.run_for(Millis{10});
  EXPECT_FALSE(streamer().vehicle_connected());
  ASSERT_TRUE(streamer().stats().last_close_reason.has_value());
  EXPECT_EQ(streamer().stats().last_close_reason->code, PeerError::truncated_frame);
  auto next = connect_vehicle_peer(sim, "truck-1");
  next->echo = true;
  sim.run_for(Millis{300});
  EXPECT_EQ(next->received_at.size(), 30u);
  EXPECT_TRUE(cadence_exact(next->received_at));
}

TEST_F(WorldBadInput, SilenceInsideAFrameClosesAfterExactlyTwoSeconds) {
  const SimTime last_byte = sim.now();
  peer->send_raw(testing::length_prefix(100) + "{\"ack");
  sim.run_until(last_byte + Millis{2000} - Micros{1});
  EXPECT_TRUE(streamer().vehicle_connected());
  EXPECT_TRUE(cadence_exact(peer->received_at)) << "a half-received frame must not disturb control";
  sim.run_until(last_byte + Millis{2000});
  EXPECT_FALSE(streamer().vehicle_connected());
  EXPECT_EQ(peer->closed_at(), last_byte + Millis{2000});
}

TEST_F(WorldBadInput, OversizedFrameIsDrainedAndTheConnectionKept) {
  peer->echo = true;
  const std::size_t frames_before = peer->received_at.size();
  std::string big = R"({"ack_time": 1, "ack_time_mac": 2, "vehicle_user_data": {"user_data": ")";
  big.append(40'000, 'x');
  big += "\"}}";
  peer->send_payload(big);
  sim.run_for(Millis{500});
  EXPECT_FALSE(peer->closed_by_peer()) << peer->close_reason();
  EXPECT_EQ(streamer().stats().oversized_frames_dropped, 1u);
  EXPECT_TRUE(cadence_exact(peer->received_at, frames_before));
  EXPECT_TRUE(streamer().faults().empty() || !streamer().faults().contains(FaultId::VehicleNoResponse));
}

TEST_F(WorldBadInput, HostileLengthIsDrainedWithoutBufferingIt) {
  // A header announcing 4 GiB, then 2 MiB of junk in small chunks: drained as it comes, the
  // connection stays (SPEC §2), control keeps its exact cadence.
  const std::size_t frames_before = peer->received_at.size();
  peer->send_raw(testing::length_prefix(0xFFFFFFFFu));
  const std::string junk(64 * 1024, 'j');
  for (int chunk = 0; chunk < 32; ++chunk) {
    peer->send_raw(junk);
    sim.run_for(Millis{10});
  }
  sim.run_for(Millis{500});
  EXPECT_FALSE(peer->closed_by_peer()) << peer->close_reason();
  EXPECT_TRUE(streamer().vehicle_connected());
  EXPECT_TRUE(cadence_exact(peer->received_at, frames_before));
}

TEST_F(WorldBadInput, FloodOfResponsesNeitherStallsNorSlowsTheWorld) {
  const std::size_t frames_before = peer->received_at.size();
  // 20 000 valid responses (about 1 MB) in one burst, then another every tick for a second.
  VehicleResponseMessage response;
  response.ack = AckPair{1, 2};
  response.vehicle_user_data = VehicleUserData{Position{57.7, 11.9}, RawJson{R"({"speed":1})"}};
  std::string json;
  encode_vehicle_response(response, json);
  std::string burst;
  for (int index = 0; index < 20'000; ++index) burst += testing::frame_of(json);
  const double cpu_start = thread_cpu_seconds();
  peer->send_raw(burst);
  for (int index = 0; index < 100; ++index) {
    peer->send_raw(burst.substr(0, burst.size() / 20));
    sim.run_for(tick);
  }
  const double cpu = thread_cpu_seconds() - cpu_start;
  EXPECT_FALSE(peer->closed_by_peer()) << peer->close_reason();
  EXPECT_GE(streamer().stats().vehicle_responses_received, 20'000u + 100u * 1000u);
  EXPECT_TRUE(cadence_exact(peer->received_at, frames_before));
  // 120 000 decodes: a generous bound that still catches quadratic buffering (a 1 MB burst
  // re-copied per frame is ~10^10 bytes moved). The virtual world runs on this thread, so its
  // CPU time is the work done, whatever else the machine runs; wall time is not.
  EXPECT_LT(cpu, 20.0);
}

TEST_F(WorldBadInput, UnknownFieldsAreIgnored) {
  peer->echo = true;
  peer->send_payload(R"({"ack_time": 1, "ack_time_mac": 2, "future_field": {"x": [1, 2]}})");
  sim.run_for(Millis{200});
  EXPECT_FALSE(peer->closed_by_peer()) << peer->close_reason();
  EXPECT_TRUE(streamer().vehicle_connected());
}

TEST_F(WorldBadInput, SecondConnectionIsRefusedAndTheFirstKeepsItsCadence) {
  const std::size_t frames_before = peer->received_at.size();
  peer->echo = true;
  auto intruder = connect_vehicle_peer(sim, "truck-1");
  sim.run_for(Millis{300});
  EXPECT_TRUE(intruder->closed_by_peer());
  EXPECT_TRUE(intruder->received_at.empty());
  EXPECT_FALSE(peer->closed_by_peer());
  EXPECT_EQ(streamer().stats().connections_refused, 1u);
  EXPECT_TRUE(cadence_exact(peer->received_at, frames_before));
}

}  // namespace
}  // namespace ocp::world_test
