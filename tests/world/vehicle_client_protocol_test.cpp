// The reference vehicle client inside a virtual-time world (issue #4): the loop closes,
// reconnects after the stream drops, and every --misbehave switch produces its fault.
#include <gtest/gtest.h>

#include <algorithm>

#include "world_fixture.hpp"

namespace ocp::world_test {
namespace {

WorldConfig misbehaving(const Misbehaviour& misbehave, std::uint64_t ack_time_offset = 0) {
  WorldConfig config = one_vehicle_config();
  config.vehicles[0].client.misbehave = misbehave;
  config.vehicles[0].streamer.ack_time_offset = ack_time_offset;
  return config;
}

constexpr std::uint64_t above_double_precision = (std::uint64_t{1} << 53) + 1;

TEST(WorldVehicleClient, LatencyLoopClosesWithTheReferenceClient) {
  VirtualWorld sim(one_vehicle_config());
  ASSERT_TRUE(sim.start());
  sim.run_for(Millis{1000});
  const VehicleClient& client = *sim.world().vehicle_client("truck-1");
  EXPECT_TRUE(client.connected());
  EXPECT_EQ(client.stats().control_messages_received, sim.world().streamer("truck-1").stats().control_frames_sent);
  EXPECT_GE(client.stats().echo_responses_sent, client.stats().control_messages_received);
  EXPECT_FALSE(sim.world().streamer("truck-1").faults().contains(FaultId::InvalidMac));
  EXPECT_FALSE(sim.world().streamer("truck-1").faults().contains(FaultId::VehicleNoResponse));
  EXPECT_TRUE(sim.world().streamer("truck-1").latency_ms().has_value());
}

TEST(WorldVehicleClient, LoopStaysClosedWithAckTimesAboveDoublePrecision) {
  VirtualWorld sim(misbehaving(Misbehaviour{}, above_double_precision));
  ASSERT_TRUE(sim.start());
  sim.run_for(Millis{1000});
  EXPECT_TRUE(sim.world().streamer("truck-1").faults().empty())
      << sim.world().streamer("truck-1").faults().fault_reason();
  EXPECT_GT(sim.world().vehicle_tap("truck-1")->last_control()->ack.ack_time, above_double_precision);
}

TEST(WorldVehicleClient, ReconnectsThroughANewPipeAfterTheStreamDrops) {
  VirtualWorld sim(one_vehicle_config());
  ASSERT_TRUE(sim.start());
  sim.run_for(Millis{1000});
  StreamerCore& streamer = sim.world().streamer("truck-1");
  ASSERT_TRUE(streamer.faults().empty());

  sim.world().drop_vehicle_connection("truck-1");
  sim.run_for(Millis{10});
  EXPECT_FALSE(streamer.vehicle_connected());
  EXPECT_TRUE(streamer.faults().contains(FaultId::VehicleNoResponse));

  // Back after the backoff (100 ms) on a fresh connection; the loop closes again.
  ASSERT_TRUE(sim.run_until_condition([&] { return streamer.vehicle_connected(); }, Millis{200}));
  EXPECT_EQ(sim.now(), SimTime{Millis{1000} + sim.world().config().reconnect_backoff});
  EXPECT_EQ(sim.world().vehicle_connections("truck-1"), 2u);
  EXPECT_EQ(streamer.stats().connections_accepted, 2u);
  sim.run_for(Millis{500});
  EXPECT_TRUE(streamer.faults().empty()) << streamer.faults().fault_reason();
  EXPECT_TRUE(sim.world().vehicle_client("truck-1")->connected());
}

TEST(WorldVehicleClient, ReconnectsAfterTheStreamerClosesTheConnection) {
  // malformed-json responses make the Streamer close the connection (SPEC §2); the client
  // comes back after its backoff each time and the world keeps running.
  Misbehaviour misbehave;
  misbehave.malformed_json = true;
  VirtualWorld sim(misbehaving(misbehave));
  ASSERT_TRUE(sim.start());
  sim.run_for(Millis{1000});
  StreamerCore& streamer = sim.world().streamer("truck-1");
  EXPECT_GE(streamer.stats().connections_closed, 2u);
  EXPECT_GE(sim.world().vehicle_connections("truck-1"), 3u);
  ASSERT_TRUE(streamer.stats().last_close_reason.has_value());
  EXPECT_EQ(streamer.stats().last_close_reason->code, PeerError::malformed_json)
      << streamer.stats().last_close_reason->message();
  EXPECT_EQ(streamer.stats().control_ticks, 101u) << "the control cadence never stalls";
}

TEST(WorldVehicleClient, StopEchoRaisesHighLatency) {
  Misbehaviour misbehave;
  misbehave.stop_echo = true;
  VirtualWorld sim(misbehaving(misbehave));
  ASSERT_TRUE(sim.start());
  StreamerCore& streamer = sim.world().streamer("truck-1");
  ASSERT_TRUE(sim.run_until_condition([&] { return streamer.faults().contains(FaultId::HighLatency); },
                                      Millis{1000}));
  // The only pair ever echoed was issued at the first tick (t = 0): it ages past 500 ms at
  // the first tick after 500 ms.
  EXPECT_EQ(sim.now(), SimTime{Millis{510}});
  EXPECT_FALSE(streamer.faults().contains(FaultId::InvalidMac)) << "the stale pair is still valid";
  sim.run_for(Millis{1000});
  EXPECT_GE(*streamer.latency_ms(), 1500u) << "the latency keeps growing";
}

TEST(WorldVehicleClient, CorruptMacRaisesInvalidMac) {
  Misbehaviour misbehave;
  misbehave.corrupt_mac = true;
  VirtualWorld sim(misbehaving(misbehave));
  ASSERT_TRUE(sim.start());
  sim.run_for(Millis{1000});
  StreamerCore& streamer = sim.world().streamer("truck-1");
  EXPECT_TRUE(streamer.faults().contains(FaultId::InvalidMac));
  EXPECT_FALSE(streamer.latency_ms().has_value()) << "no valid pair ever returned";
  EXPECT_GT(streamer.stats().invalid_returned_pairs, 90u);
  EXPECT_TRUE(sim.world().vehicle_client("truck-1")->safety().safe_state);
}

TEST(WorldVehicleClient, AckThroughDoubleBreaksTheLoopAboveTwoToTheFiftyThird) {
  Misbehaviour misbehave;
  misbehave.ack_through_double = true;
  VirtualWorld sim(misbehaving(misbehave, above_double_precision));
  ASSERT_TRUE(sim.start());
  sim.run_for(Millis{1000});
  EXPECT_TRUE(sim.world().streamer("truck-1").faults().contains(FaultId::InvalidMac));
  EXPECT_FALSE(sim.world().streamer("truck-1").latency_ms().has_value());
}

TEST(WorldVehicleClient, AckThroughDoubleIsHarmlessBelowTwoToTheFiftyThird) {
  Misbehaviour misbehave;
  misbehave.ack_through_double = true;
  VirtualWorld sim(misbehaving(misbehave, 0));
  ASSERT_TRUE(sim.start());
  sim.run_for(Millis{1000});
  EXPECT_TRUE(sim.world().streamer("truck-1").faults().empty())
      << "the conformance suite needs offsets >= 2^53 to catch this";
}

TEST(WorldVehicleClient, DelayedResponsesRaiseTheMeasuredLatency) {
  VirtualWorld baseline(one_vehicle_config());
  ASSERT_TRUE(baseline.start());
  baseline.run_for(Millis{2000});
  const std::uint64_t base_ms = *baseline.world().streamer("truck-1").latency_ms();

  Misbehaviour misbehave;
  misbehave.delay_responses = Millis{200};
  VirtualWorld sim(misbehaving(misbehave));
  ASSERT_TRUE(sim.start());
  sim.run_for(Millis{2000});
  const std::uint64_t delayed_ms = *sim.world().streamer("truck-1").latency_ms();
  EXPECT_GE(delayed_ms, 200u);
  EXPECT_GE(delayed_ms, base_ms + 150u);
  EXPECT_FALSE(sim.world().streamer("truck-1").faults().contains(FaultId::HighLatency));

  misbehave.delay_responses = Millis{600};
  VirtualWorld slow(misbehaving(misbehave));
  ASSERT_TRUE(slow.start());
  slow.run_for(Millis{2000});
  EXPECT_TRUE(slow.world().streamer("truck-1").faults().contains(FaultId::HighLatency));
}

TEST(WorldVehicleClient, OversizedFramesAreDroppedAndCountedAndTheConnectionIsKept) {
  Misbehaviour misbehave;
  misbehave.oversized_frames = true;
  VirtualWorld sim(misbehaving(misbehave));
  ASSERT_TRUE(sim.start());
  sim.run_for(Millis{3000});
  StreamerCore& streamer = sim.world().streamer("truck-1");
  EXPECT_GT(streamer.stats().oversized_frames_dropped, 200u);
  EXPECT_EQ(streamer.stats().connections_closed, 0u) << streamer.stats().last_close_reason.value_or(CloseReason{}).message();
  EXPECT_TRUE(streamer.vehicle_connected());
  EXPECT_EQ(streamer.stats().vehicle_responses_received, 0u);
  // Nothing usable was echoed: the loop never closed.
  EXPECT_TRUE(streamer.faults().contains(FaultId::InvalidMac));
  // SPEC §2: each drained frame is logged as a warning naming its size.
  const auto warnings = sim.log().lines_containing(" WARN: ");
  EXPECT_TRUE(std::any_of(warnings.begin(), warnings.end(), [](const std::string& line) {
    return line.find("16385") != std::string::npos;
  })) << "no warning names the 16385-byte frame";
}

TEST(WorldVehicleClient, SilentClientIsClosedAfterExactlyTwoSeconds) {
  Misbehaviour misbehave;
  misbehave.silent = true;
  VirtualWorld sim(misbehaving(misbehave));
  ASSERT_TRUE(sim.start());
  StreamerCore& streamer = sim.world().streamer("truck-1");
  sim.run_until(SimTime{Millis{2000}} - Micros{1});
  EXPECT_TRUE(streamer.vehicle_connected());
  sim.run_until(SimTime{Millis{2000}});
  EXPECT_FALSE(streamer.vehicle_connected());
  EXPECT_EQ(streamer.stats().connections_closed, 1u);
}

}  // namespace
}  // namespace ocp::world_test
