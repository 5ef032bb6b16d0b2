// The 10 ms control tick (SPEC §3.2): cadence, repeat-last-command, default controller on
// control-path faults, null controller, user data, NoControlMessage timing.
#include "streamer_harness.hpp"

namespace ocp::streamer_test {
namespace {

Controller driving_controller() {
  Controller controller;
  controller.buttons.a = true;
  controller.axes.left_x = 0.5;
  controller.axes.right_trigger = 0.25;
  return controller;
}

TEST(StreamerControlTick, SendsOneFrameEvery10MsOnAbsoluteDeadlines) {
  StreamerHarness harness;
  TestVehicle& vehicle = harness.connect_vehicle();
  harness.core.start();
  harness.executor.run_until(ms(1000) - Micros{1});

  ASSERT_EQ(vehicle.received.size(), 100u);
  for (std::size_t k = 0; k < vehicle.received.size(); ++k) {
    EXPECT_EQ(vehicle.received_at[k], ms(static_cast<std::int64_t>(10 * k)));
    EXPECT_EQ(vehicle.received[k].ack.ack_time, 10'000u * k);
  }
  EXPECT_EQ(harness.core.stats().control_frames_sent, 100u);
}

TEST(StreamerControlTick, SendsNothingWhileNoVehicleIsConnected) {
  StreamerHarness harness;
  harness.core.start();
  harness.executor.run_until(ms(500));
  EXPECT_EQ(harness.core.stats().control_frames_sent, 0u);
  EXPECT_EQ(harness.core.stats().control_ticks, 51u);
}

TEST(StreamerControlTick, EveryFrameCarriesAFreshValidAckPair) {
  StreamerHarness harness;
  TestVehicle& vehicle = harness.connect_vehicle();
  harness.core.start();
  harness.executor.run_until(ms(200));
  AckMac mac(test_key());
  ASSERT_FALSE(vehicle.received.empty());
  for (const auto& message : vehicle.received) {
    EXPECT_TRUE(mac.verify(message.ack.ack_time, message.ack.ack_time_mac));
  }
}

TEST(StreamerControlTick, RepeatsTheLastOperatorCommand) {
  StreamerHarness harness;
  TestVehicle& vehicle = harness.connect_vehicle();
  harness.core.start();
  harness.executor.run_until(ms(5));
  harness.send_control(harness.control_returning(harness.pair_issued_at(ms(0)), driving_controller()));
  harness.executor.run_until(ms(300));

  // Frames at 10 … 300 ms all repeat the single command received at 5 ms.
  ASSERT_EQ(vehicle.received.size(), 31u);
  EXPECT_EQ(vehicle.received[0].controller, Controller::safe_default());
  for (std::size_t k = 1; k < vehicle.received.size(); ++k) {
    EXPECT_EQ(vehicle.received[k].controller, driving_controller()) << k;
  }
}

TEST(StreamerControlTick, DefaultControllerWhileAControlPathFaultIsActive) {
  StreamerHarness harness;
  TestVehicle& vehicle = harness.connect_vehicle();
  harness.core.start();
  harness.schedule_controls(ms(5), ms(995), Micros{10'000}, [&harness](SimTime now) {
    OperatorControl control =
        harness.control_returning(harness.pair_issued_at(now - ms(5)), driving_controller());
    if (now >= ms(105) && now < ms(205)) control.sender_faults = {FaultId::InputLost};
    return control;
  });
  harness.executor.run_until(ms(300));

  for (std::size_t k = 0; k < vehicle.received.size(); ++k) {
    const SimTime at = vehicle.received_at[k];
    const auto& message = vehicle.received[k];
    if (at >= ms(110) && at <= ms(200)) {
      EXPECT_EQ(message.controller, Controller::safe_default()) << at.count();
      EXPECT_TRUE(message.telemetry.fault);
      EXPECT_EQ(message.telemetry.fault_reason, "Operator Station Has Error");
    } else if (at >= ms(10)) {
      EXPECT_EQ(message.controller, driving_controller()) << at.count();
      EXPECT_FALSE(message.telemetry.fault);
      EXPECT_EQ(message.telemetry.fault_reason, "");
    }
  }
  EXPECT_EQ(harness.observer.changes(FaultId::OperatorStationHasError, true),
            std::vector<SimTime>{ms(105)});
  EXPECT_EQ(harness.observer.changes(FaultId::OperatorStationHasError, false),
            std::vector<SimTime>{ms(205)});
}

TEST(StreamerControlTick, NullControllerStaysNullEvenDuringFaults) {
  StreamerHarness harness;
  TestVehicle& vehicle = harness.connect_vehicle();
  harness.core.start();
  harness.schedule_controls(ms(5), ms(195), Micros{10'000}, [&harness](SimTime now) {
    OperatorControl control = harness.control_returning(harness.pair_issued_at(now), std::nullopt);
    if (now >= ms(100)) control.returned_ack.reset();  // InvalidMac from here on
    return control;
  });
  harness.executor.run_until(ms(200));
  EXPECT_TRUE(harness.core.faults().contains(FaultId::InvalidMac));
  ASSERT_EQ(vehicle.received.size(), 21u);
  for (std::size_t k = 1; k < vehicle.received.size(); ++k) {
    EXPECT_FALSE(vehicle.received[k].controller.has_value()) << k;
  }
  EXPECT_FALSE(harness.core.last_sent_controller().has_value());
}

TEST(StreamerControlTick, PassesClientUserDataFromTheLatestOperatorMessage) {
  StreamerHarness harness;
  TestVehicle& vehicle = harness.connect_vehicle();
  harness.core.start();
  harness.executor.run_until(ms(5));
  OperatorControl with_data = harness.control_returning(harness.pair_issued_at(ms(0)));
  with_data.client_user_data = RawJson{R"({"mode":"dig","n":18446744073709551615})"};
  harness.send_control(std::move(with_data));
  harness.executor.run_until(ms(15));
  harness.send_control(harness.control_returning(harness.pair_issued_at(ms(10))));
  harness.executor.run_until(ms(20));

  ASSERT_EQ(vehicle.received.size(), 3u);
  EXPECT_FALSE(vehicle.received[0].client_user_data.has_value());
  ASSERT_TRUE(vehicle.received[1].client_user_data.has_value());
  EXPECT_EQ(vehicle.received[1].client_user_data->text, R"({"mode":"dig","n":18446744073709551615})");
  EXPECT_FALSE(vehicle.received[2].client_user_data.has_value());
  EXPECT_EQ(vehicle.raw_payloads[2].find("client_user_data"), std::string::npos);
}

TEST(StreamerControlTick, OversizedClientUserDataIsDroppedButControlStillFlows) {
  StreamerHarness harness;
  TestVehicle& vehicle = harness.connect_vehicle();
  harness.core.start();
  harness.executor.run_until(ms(5));
  OperatorControl huge = harness.control_returning(harness.pair_issued_at(ms(0)), driving_controller());
  huge.client_user_data = RawJson{"\"" + std::string(20'000, 'u') + "\""};
  harness.send_control(std::move(huge));
  harness.executor.run_until(ms(30));
  ASSERT_EQ(vehicle.received.size(), 4u);
  for (std::size_t k = 1; k < vehicle.received.size(); ++k) {
    EXPECT_EQ(vehicle.received[k].controller, driving_controller());
    EXPECT_FALSE(vehicle.received[k].client_user_data.has_value());
  }
  EXPECT_EQ(harness.core.stats().control_user_data_dropped, 3u);
  for (const auto& payload : vehicle.raw_payloads) EXPECT_LE(payload.size(), max_payload_bytes);
}

std::vector<std::string> lines_with(const StreamerHarness& harness, std::string_view needle) {
  std::vector<std::string> found;
  for (const auto& line : harness.log.lines()) {
    if (line.message.find(needle) != std::string::npos) found.push_back(line.message);
  }
  return found;
}

// Issue #19 item 6: one ~16 KB user data made this line 100 times a second, on and on (the
// Player keeps the client's last user data after the client left). Now: once, then a count
// every 5 s while it lasts, and one last count when it ends.
TEST(StreamerControlTick, OversizedClientUserDataIsWarnedOnceThenCounted) {
  StreamerHarness harness;
  harness.connect_vehicle().echo = true;   // stays connected
  harness.core.start();
  harness.executor.run_until(ms(5));
  OperatorControl huge = harness.control_returning(harness.pair_issued_at(ms(0)), driving_controller());
  huge.client_user_data = RawJson{"\"" + std::string(16'500, 'u') + "\""};
  harness.send_control(std::move(huge));
  harness.executor.run_until(ms(10'015));
  EXPECT_EQ(harness.core.stats().control_user_data_dropped, 1001u);   // ticks at 10 … 10 010 ms
  std::vector<std::string> lines = lines_with(harness, "sent without client_user_data");
  ASSERT_EQ(lines.size(), 3u) << ::testing::PrintToString(lines);
  EXPECT_NE(lines[0].find("control message of 1"), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find("exceeds 16384 bytes"), std::string::npos) << lines[0];
  EXPECT_EQ(lines[1], "control message over 16384 bytes: sent without client_user_data 500 times in the last 5 s");
  EXPECT_EQ(lines[2], "control message over 16384 bytes: sent without client_user_data 500 times in the last 5 s");

  // User data that fits ends the episode: at most one last count, then silence; the next
  // episode is told in full again.
  harness.send_control(harness.control_returning(harness.pair_issued_at(ms(10'000)), driving_controller()));
  harness.executor.run_until(ms(30'000));
  const std::uint64_t dropped = harness.core.stats().control_user_data_dropped;
  lines = lines_with(harness, "sent without client_user_data");
  ASSERT_EQ(lines.size(), dropped == 1001u ? 3u : 4u) << ::testing::PrintToString(lines);
  OperatorControl again = harness.control_returning(harness.pair_issued_at(ms(29'990)), driving_controller());
  again.client_user_data = RawJson{"\"" + std::string(16'500, 'u') + "\""};
  harness.send_control(std::move(again));
  harness.executor.run_until(ms(30'100));
  const std::size_t before = lines.size();
  lines = lines_with(harness, "sent without client_user_data");
  ASSERT_EQ(lines.size(), before + 1) << ::testing::PrintToString(lines);
  EXPECT_NE(lines.back().find("control message of 1"), std::string::npos) << lines.back();
}

TEST(StreamerControlTick, NoControlMessageRaisedAtFirstTickAfter1000MsOfSilence) {
  StreamerHarness harness;
  harness.connect_vehicle();
  harness.core.start();
  harness.executor.run_until(ms(505));
  harness.send_control(harness.control_returning(harness.pair_issued_at(ms(500))));
  harness.executor.run_until(ms(2000));
  // Last message at 505 ms: 1505 is not a tick, 1510 is the first tick strictly after.
  EXPECT_EQ(harness.observer.changes(FaultId::NoControlMessage, true),
            std::vector<SimTime>{ms(1510)});
  harness.send_control(harness.control_returning(harness.pair_issued_at(ms(1990))));
  EXPECT_FALSE(harness.core.faults().contains(FaultId::NoControlMessage));
  EXPECT_EQ(harness.observer.changes(FaultId::NoControlMessage, false),
            std::vector<SimTime>{ms(2000)});
  EXPECT_TRUE(harness.logged("fault raised: No Control Message"));
  EXPECT_TRUE(harness.logged("fault cleared: No Control Message"));
}

TEST(StreamerControlTick, NoControlMessageIsNotRaisedAtExactly1000Ms) {
  StreamerHarness harness;
  harness.connect_vehicle();
  harness.core.start();
  harness.executor.run_until(ms(500));
  harness.send_control(harness.control_returning(harness.pair_issued_at(ms(500))));
  harness.executor.run_until(ms(1500));
  EXPECT_FALSE(harness.core.faults().contains(FaultId::NoControlMessage));
  harness.executor.run_until(ms(1510));
  EXPECT_TRUE(harness.core.faults().contains(FaultId::NoControlMessage));
}

TEST(StreamerControlTick, NoControlMessageMeasuredFromStartWhenNoneEverArrived) {
  StreamerHarness harness;
  TestVehicle& vehicle = harness.connect_vehicle();
  harness.core.start();
  harness.executor.run_until(ms(1100));
  EXPECT_EQ(harness.observer.changes(FaultId::NoControlMessage, true),
            std::vector<SimTime>{ms(1010)});
  EXPECT_EQ(vehicle.received.back().telemetry.fault_reason, "No Control Message");
  EXPECT_EQ(vehicle.received.back().controller, Controller::safe_default());
}

TEST(StreamerControlTick, TelemetryLatencyIsZeroBeforeAnyMeasurement) {
  StreamerHarness harness;
  TestVehicle& vehicle = harness.connect_vehicle();
  harness.core.start();
  harness.executor.run_until(ms(50));
  ASSERT_FALSE(vehicle.received.empty());
  EXPECT_EQ(vehicle.received.front().telemetry.latency_ms, 0u);
  EXPECT_FALSE(harness.core.latency_ms().has_value());
}

}  // namespace
}  // namespace ocp::streamer_test
