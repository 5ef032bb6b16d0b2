// The latency loop (SPEC §5): MAC validation of returned pairs, latency measurement from the
// newest valid pair re-evaluated every tick, HighLatency, InvalidMac, ack_time_offset ≥ 2^53.
#include "streamer_harness.hpp"

namespace ocp::streamer_test {
namespace {

TEST(StreamerLatencyLoop, LatencyIsNowMinusIssueTimeOfNewestValidPair) {
  StreamerHarness harness;
  TestVehicle& vehicle = harness.connect_vehicle();
  harness.core.start();
  harness.executor.run_until(ms(142) + Micros{500});
  harness.send_control(harness.control_returning(harness.pair_issued_at(ms(100))));
  EXPECT_EQ(harness.core.latency_ms(), 42u);  // 42.5 ms, whole milliseconds
  harness.executor.run_until(ms(150));
  EXPECT_EQ(vehicle.received.back().telemetry.latency_ms, 50u);
  // An older (reordered) valid pair does not replace the newest one.
  harness.send_control(harness.control_returning(harness.pair_issued_at(ms(20))));
  EXPECT_EQ(harness.core.latency_ms(), 50u);
}

TEST(StreamerLatencyLoop, HighLatencyWhenReturnedPairIsOlderThan500MsAndClearedWhenFresh) {
  StreamerHarness harness;
  harness.connect_vehicle();
  harness.core.start();
  // The operator keeps returning the pair issued at 0 ms until 695 ms, then fresh ones.
  harness.schedule_controls(ms(5), ms(995), Micros{10'000}, [&harness](SimTime now) {
    return harness.control_returning(now < ms(700) ? harness.pair_issued_at(ms(0))
                                                   : harness.pair_issued_at(now - ms(40)));
  });
  harness.executor.run_until(ms(1000));
  // Tick at 500 ms: 500 ms is not > 500 ms; the message at 505 ms sees 505 ms.
  EXPECT_EQ(harness.observer.changes(FaultId::HighLatency, true), std::vector<SimTime>{ms(505)});
  EXPECT_EQ(harness.observer.changes(FaultId::HighLatency, false), std::vector<SimTime>{ms(705)});
  EXPECT_EQ(harness.core.latency_ms(), 45u);
}

TEST(StreamerLatencyLoop, StalledLoopShowsGrowingLatencyAtEveryTick) {
  StreamerHarness harness;
  TestVehicle& vehicle = harness.connect_vehicle();
  harness.core.start();
  harness.executor.run_until(ms(105));
  harness.send_control(harness.control_returning(harness.pair_issued_at(ms(100))));
  // No more operator messages: the latency keeps growing from the same pair.
  harness.executor.run_until(ms(700));
  EXPECT_EQ(harness.observer.changes(FaultId::HighLatency, true), std::vector<SimTime>{ms(610)});
  for (std::size_t k = 0; k < vehicle.received.size(); ++k) {
    if (vehicle.received_at[k] >= ms(110)) {
      EXPECT_EQ(vehicle.received[k].telemetry.latency_ms,
                static_cast<std::uint64_t>(to_whole_ms(vehicle.received_at[k] - ms(100))));
    }
  }
}

TEST(StreamerLatencyLoop, InvalidMacOnFlippedBitOrMissingPairAndClearedByValidPair) {
  StreamerHarness harness;
  harness.connect_vehicle();
  harness.core.start();
  harness.executor.run_until(ms(5));
  harness.send_control(harness.control_returning(harness.pair_issued_at(ms(0))));
  EXPECT_FALSE(harness.core.faults().contains(FaultId::InvalidMac));

  harness.executor.run_until(ms(15));
  AckPair flipped_mac = harness.pair_issued_at(ms(10));
  flipped_mac.ack_time_mac ^= 0x1u;
  harness.send_control(harness.control_returning(flipped_mac));
  EXPECT_TRUE(harness.core.faults().contains(FaultId::InvalidMac));

  harness.executor.run_until(ms(25));
  harness.send_control(harness.control_returning(harness.pair_issued_at(ms(20))));
  EXPECT_FALSE(harness.core.faults().contains(FaultId::InvalidMac));

  harness.executor.run_until(ms(35));
  AckPair flipped_time = harness.pair_issued_at(ms(30));
  flipped_time.ack_time ^= 0x100u;
  harness.send_control(harness.control_returning(flipped_time));
  EXPECT_TRUE(harness.core.faults().contains(FaultId::InvalidMac));

  harness.executor.run_until(ms(45));
  harness.send_control(harness.control_returning(harness.pair_issued_at(ms(40))));
  harness.executor.run_until(ms(55));
  harness.send_control(harness.control_returning(std::nullopt));
  EXPECT_TRUE(harness.core.faults().contains(FaultId::InvalidMac));

  EXPECT_EQ(harness.observer.changes(FaultId::InvalidMac, true),
            (std::vector<SimTime>{ms(15), ms(35), ms(55)}));
  EXPECT_EQ(harness.observer.changes(FaultId::InvalidMac, false),
            (std::vector<SimTime>{ms(25), ms(45)}));
  EXPECT_EQ(harness.core.stats().invalid_returned_pairs, 3u);
  EXPECT_TRUE(harness.logged("fault raised: Latency Loop Not Closed"));
}

TEST(StreamerLatencyLoop, InvalidPairDoesNotUpdateLatency) {
  StreamerHarness harness;
  harness.connect_vehicle();
  harness.core.start();
  harness.executor.run_until(ms(100));
  harness.send_control(harness.control_returning(harness.pair_issued_at(ms(90))));
  AckPair forged = harness.pair_issued_at(ms(99));
  forged.ack_time_mac += 1;
  harness.send_control(harness.control_returning(forged));
  EXPECT_EQ(harness.core.latency_ms(), 10u);
}

TEST(StreamerLatencyLoop, InvalidMacIsNotRaisedBeforeTheFirstOperatorMessage) {
  StreamerHarness harness;
  harness.connect_vehicle();
  harness.core.start();
  harness.executor.run_until(ms(3000));
  EXPECT_FALSE(harness.core.faults().contains(FaultId::InvalidMac));
  EXPECT_TRUE(harness.core.faults().contains(FaultId::NoControlMessage));
}

TEST(StreamerLatencyLoop, MacKeyIsRandomWhenNotConfigured) {
  StreamerConfig config = test_config();
  config.mac_key.reset();
  StreamerHarness first(config);
  StreamerHarness second(config);
  TestVehicle& first_vehicle = first.connect_vehicle();
  TestVehicle& second_vehicle = second.connect_vehicle();
  first.core.start();
  second.core.start();
  first.executor.run_until(ms(0));
  second.executor.run_until(ms(0));
  ASSERT_EQ(first_vehicle.received.size(), 1u);
  ASSERT_EQ(second_vehicle.received.size(), 1u);
  EXPECT_EQ(first_vehicle.received[0].ack.ack_time, second_vehicle.received[0].ack.ack_time);
  EXPECT_NE(first_vehicle.received[0].ack.ack_time_mac, second_vehicle.received[0].ack.ack_time_mac);
}

// Offsets above 2^53 (and one that wraps past 2^64) survive byte-exact end to end:
// Streamer → vehicle frame → vehicle echo → SEI → operator → Streamer.
class StreamerLargeOffset : public ::testing::TestWithParam<std::uint64_t> {};

TEST_P(StreamerLargeOffset, AckTimeOffsetWorksEndToEnd) {
  StreamerConfig config = test_config();
  config.ack_time_offset = GetParam();
  StreamerHarness harness(config);
  TestVehicle& vehicle = harness.connect_vehicle();
  vehicle.echo = true;
  harness.core.start();
  // The fake Player returns whatever pair the newest video frame carried.
  harness.schedule_controls(ms(5), ms(995), Micros{10'000}, [&harness](SimTime) {
    std::optional<AckPair> sei;
    for (const auto& [at, frame] : harness.received_of<VideoFrame>()) {
      if (frame.sei) sei = frame.sei;
    }
    return harness.control_returning(sei);
  });
  harness.executor.run_until(ms(1000));

  ASSERT_EQ(vehicle.received.size(), 101u);
  for (std::size_t k = 0; k < vehicle.received.size(); ++k) {
    EXPECT_EQ(vehicle.received[k].ack.ack_time, GetParam() + 10'000u * k);
  }
  EXPECT_FALSE(harness.core.faults().contains(FaultId::InvalidMac));
  // Newest SEI at 995 ms came from the 30 fps frame at 966.667 ms, which carried the pair
  // issued at the 960 ms tick: latency 40 ms at the 1000 ms tick.
  EXPECT_EQ(vehicle.received.back().telemetry.latency_ms, 40u);
  EXPECT_EQ(harness.core.latency_ms(), 40u);
  EXPECT_TRUE(harness.core.faults().empty());
}

INSTANTIATE_TEST_SUITE_P(Offsets, StreamerLargeOffset,
                         ::testing::Values(std::uint64_t{0}, (std::uint64_t{1} << 53) + 1,
                                           std::uint64_t{0xFFFFFFFFFFFFFFFFull} - 50'000));

TEST(StreamerLatencyLoop, VehicleResponsePairsAreKeptUnvalidatedForSei) {
  StreamerHarness harness;
  TestVehicle& vehicle = harness.connect_vehicle();
  harness.core.start();
  harness.executor.run_until(ms(10));
  vehicle.send_response(VehicleResponseMessage{AckPair{123, 456}, std::nullopt});
  harness.executor.run_until(ms(40));
  EXPECT_EQ(harness.core.latest_echoed_pair(), (AckPair{123, 456}));
  const auto frames = harness.received_of<VideoFrame>();
  ASSERT_EQ(frames.size(), 2u);  // 0 ms and 33.333 ms
  EXPECT_FALSE(frames[0].second.sei.has_value());
  EXPECT_EQ(frames[1].second.sei, (AckPair{123, 456}));
}

}  // namespace
}  // namespace ocp::streamer_test
