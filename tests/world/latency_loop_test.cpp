// One vehicle, no impairments: the whole pipeline of ARCHITECTURE.md's "one control tick"
// runs end to end in virtual time with the reference vehicle client attached over a pipe.
#include <gtest/gtest.h>

#include "world_fixture.hpp"

namespace ocp::world_test {
namespace {

TEST(World, LatencyLoopClosesAndStaysFaultFreeWithoutImpairments) {
  VirtualWorld sim(one_vehicle_config());
  ASSERT_TRUE(sim.start());
  sim.world().player().gamepad().set_constant(driving_controller());
  sim.run_for(Millis{300});

  StreamerCore& streamer = sim.world().streamer("truck-1");
  const std::uint64_t invalid_before = streamer.stats().invalid_returned_pairs;
  // From here on, at every tick: no fault on either side, and the loop keeps turning.
  for (int step = 0; step < 170; ++step) {
    sim.run_for(tick);
    ASSERT_TRUE(streamer.faults().empty())
        << "at " << sim.now().count() << " µs: " << streamer.faults().fault_reason();
    ASSERT_TRUE(sim.world().player().sender_faults("truck-1").empty()) << "at " << sim.now().count();
    const VehicleFeedback& feedback = sim.world().player().last_shared().vehicle_feedback.at("truck-1");
    ASSERT_TRUE(feedback.receiver_fault.empty()) << "at " << sim.now().count();
    ASSERT_TRUE(feedback.sender_fault.empty()) << "at " << sim.now().count();
  }
  EXPECT_EQ(streamer.stats().invalid_returned_pairs, invalid_before);
  EXPECT_TRUE(sim.trace().lines_containing(R"("fault":"InvalidMac","active":true)").size() <= 1)
      << "the loop may only be open before the first SEI pair came back";
}

TEST(World, TelemetryLatencyMatchesThePipelineDelay) {
  WorldConfig config = one_vehicle_config();
  config.vehicles[0].to_streamer = delay_of(Millis{40});
  config.vehicles[0].to_player = delay_of(Millis{40});
  VirtualWorld sim(config);
  ASSERT_TRUE(sim.start());
  sim.run_for(Millis{2000});

  // Round trip = both link delays + waiting for the next camera frame (≤ 1/30 s) + waiting
  // for the next Player frame (≤ 10 ms) + the age of the pair at the tick that reports it.
  const auto* tap = sim.world().vehicle_tap("truck-1");
  ASSERT_NE(tap, nullptr);
  ASSERT_TRUE(tap->last_control().has_value());
  const std::uint64_t latency_ms = tap->last_control()->telemetry.latency_ms;
  EXPECT_GE(latency_ms, 80u);
  EXPECT_LE(latency_ms, 80u + 34u + 10u + 10u);
  EXPECT_EQ(sim.world().streamer("truck-1").latency_ms(), latency_ms);
  // The Player shows the same measurement in its feedback (one feedback interval behind).
  const VehicleFeedback& feedback = sim.world().player().last_shared().vehicle_feedback.at("truck-1");
  ASSERT_TRUE(feedback.message_latency_roundtrip.has_value());
  EXPECT_GE(*feedback.message_latency_roundtrip, 80u);
  EXPECT_LE(*feedback.message_latency_roundtrip, 80u + 34u + 10u + 10u);
  EXPECT_TRUE(sim.world().streamer("truck-1").faults().empty());
}

TEST(World, VehicleUserDataReachesThePlayerFeedback) {
  VirtualWorld sim(one_vehicle_config());
  ASSERT_TRUE(sim.start());
  sim.run_for(Millis{500});

  const VehicleFeedback& feedback = sim.world().player().last_shared().vehicle_feedback.at("truck-1");
  ASSERT_TRUE(feedback.vehicle_data.has_value());
  ASSERT_TRUE(feedback.vehicle_data->pos.has_value());
  const VehicleClient* client = sim.world().vehicle_client("truck-1");
  ASSERT_NE(client, nullptr);
  EXPECT_NEAR(feedback.vehicle_data->pos->lat, client->config().start.lat, 1e-3);
  EXPECT_NEAR(feedback.vehicle_data->pos->lon, client->config().start.lon, 1e-3);
  const Status valid = validate_raw_json(feedback.vehicle_data->user_data.text);
  EXPECT_TRUE(valid) << (valid ? "" : valid.error().message()) << "\n" << feedback.vehicle_data->user_data.text;
  EXPECT_NE(feedback.vehicle_data->user_data.text.find("drive_state"), std::string::npos)
      << feedback.vehicle_data->user_data.text;
  EXPECT_LT(feedback.ms_since_last_vehicle_data, 100u);
}

TEST(World, ConstantGamepadInputReachesTheVehicleClient) {
  VirtualWorld sim(one_vehicle_config());
  ASSERT_TRUE(sim.start());
  sim.world().player().gamepad().set_constant(driving_controller());
  sim.run_for(Millis{500});

  const StreamTap* tap = sim.world().vehicle_tap("truck-1");
  ASSERT_NE(tap, nullptr);
  ASSERT_TRUE(tap->last_control().has_value());
  ASSERT_TRUE(tap->last_control()->controller.has_value());
  EXPECT_EQ(*tap->last_control()->controller, driving_controller());
  EXPECT_FALSE(tap->last_control()->telemetry.fault);
  EXPECT_EQ(tap->undecodable_frames(), 0u);
  // The Player reports what it last sent, and the Streamer what it passed on.
  EXPECT_EQ(sim.world().player().last_shared().last_input, driving_controller());
  EXPECT_EQ(sim.world().streamer("truck-1").last_sent_controller(), driving_controller());
  // The client's request follows the gamepad: right trigger → throttle.
  EXPECT_GT(sim.world().vehicle_client("truck-1")->safety().requested.throttle, 0.0);
}

TEST(World, ControlFramesReachTheVehicleEveryTenMilliseconds) {
  VirtualWorld sim(one_vehicle_config());
  ASSERT_TRUE(sim.start());
  sim.run_for(Millis{1000});
  const StreamTap* tap = sim.world().vehicle_tap("truck-1");
  // Ticks at 0, 10, …, 1000 ms, each with a vehicle connected.
  EXPECT_EQ(tap->control_messages(), 101u);
  EXPECT_EQ(tap->last_control_time(), SimTime{Millis{1000}});
  EXPECT_EQ(sim.world().streamer("truck-1").stats().control_frames_sent, 101u);
}

TEST(World, TwoVehiclesWithoutFleetIsAConfigurationError) {
  WorldConfig config = one_vehicle_config();
  config.vehicles.push_back(vehicle_spec("truck-2"));
  VirtualWorld sim(config);
  const Status status = sim.start();
  ASSERT_FALSE(status);
  EXPECT_FALSE(sim.world().running());
  EXPECT_EQ(sim.executor().pending(), 0u) << "nothing may be left running";
}

TEST(World, DuplicateVehicleNamesAreAConfigurationError) {
  WorldConfig config = one_vehicle_config();
  config.player.fleet = true;
  config.vehicles.push_back(vehicle_spec("truck-1"));
  VirtualWorld sim(config);
  const Status status = sim.start();
  ASSERT_FALSE(status);
  EXPECT_NE(status.error().detail.find("truck-1"), std::string::npos);
}

}  // namespace
}  // namespace ocp::world_test
