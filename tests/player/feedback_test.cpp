// The VehicleOcpShared object (SPEC §4.1), NoFeedbackMessage timing, ping latency and
// unknown vehicle names in client data.
#include <gtest/gtest.h>

#include "player_harness.hpp"

namespace ocp::testing {
namespace {

TEST(Player, NoFeedbackMessageRaisedAtFirstFrameAfterTimeoutFromStart) {
  PlayerHarness harness;
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.start();
  harness.run_until(at_ms(1000));
  EXPECT_FALSE(harness.player.sender_faults("truck-1").contains(FaultId::NoFeedbackMessage));
  harness.run_until(at_ms(1010));
  EXPECT_TRUE(harness.player.sender_faults("truck-1").contains(FaultId::NoFeedbackMessage));
}

TEST(Player, NoFeedbackMessageMeasuredFromLastFeedbackAndClearedByNext) {
  PlayerHarness harness;
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.start();
  harness.deliver_at(SimTime{500'000}, "truck-1", LinkMessage{StreamerFeedback{}});
  harness.run_until(at_ms(1500));  // exactly 1000 ms since the feedback: not yet
  EXPECT_FALSE(harness.player.sender_faults("truck-1").contains(FaultId::NoFeedbackMessage));
  harness.run_until(at_ms(1510));
  EXPECT_TRUE(harness.player.sender_faults("truck-1").contains(FaultId::NoFeedbackMessage));
  const auto raised = harness.control_at("truck-1", at_ms(1510));
  ASSERT_TRUE(raised.has_value());
  EXPECT_EQ(raised->sender_faults, std::vector<FaultId>{FaultId::NoFeedbackMessage});
  EXPECT_EQ(harness.player.last_shared().vehicle_feedback.at("truck-1").sender_fault,
            std::vector<std::string>{"NoFeedbackMessage"});

  harness.deliver_at(at_ms(1515), "truck-1", LinkMessage{StreamerFeedback{}});
  harness.run_until(at_ms(1520));
  EXPECT_TRUE(harness.player.sender_faults("truck-1").empty());
}

TEST(Player, NoFeedbackTimeoutIsConfigurableAndExact) {
  PlayerConfig config;
  config.no_feedback_timeout = Micros{250'000};
  PlayerHarness harness(config);
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.start();
  harness.deliver_at(SimTime{3'000}, "truck-1", LinkMessage{StreamerFeedback{}});
  harness.run_until(at_ms(250));  // 247 ms
  EXPECT_FALSE(harness.player.sender_faults("truck-1").contains(FaultId::NoFeedbackMessage));
  harness.run_until(at_ms(260));  // 257 ms
  EXPECT_TRUE(harness.player.sender_faults("truck-1").contains(FaultId::NoFeedbackMessage));
}

TEST(Player, FeedbackObjectCarriesWhatTheStreamerReported) {
  PlayerHarness harness;
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.start();
  harness.run_until(at_ms(0));
  {
    const VehicleFeedback& empty = harness.player.last_shared().vehicle_feedback.at("truck-1");
    EXPECT_EQ(empty.message_latency_roundtrip, std::nullopt);
    EXPECT_EQ(empty.missing_cameras, std::nullopt);
    EXPECT_EQ(empty.vehicle_data, std::nullopt);
    EXPECT_EQ(empty.last_remote_input, std::nullopt);
    EXPECT_TRUE(empty.receiver_fault.empty());
    EXPECT_FALSE(empty.is_monitor);
  }

  StreamerFeedback feedback;
  feedback.receiver_faults = {FaultId::CameraLost, FaultId::HighLatency};
  feedback.latency_ms = 80;
  feedback.missing_cameras = {"rear"};
  VehicleUserData data;
  data.pos = Position{57.7, 11.9};
  data.user_data = RawJson{R"({"speed":3})"};
  feedback.vehicle_data = data;
  feedback.vehicle_data_age = Micros{7'000};
  Controller remote;
  remote.buttons.y = true;
  feedback.last_remote_input = remote;
  harness.deliver_at(at_ms(100), "truck-1", LinkMessage{feedback});
  harness.video_at(at_ms(101), "truck-1", AckPair{18'446'744'073'709'551'615ULL, 4'294'967'295U});
  harness.run_until(at_ms(120));

  const VehicleFeedback& entry = harness.player.last_shared().vehicle_feedback.at("truck-1");
  EXPECT_EQ(entry.message_latency_roundtrip, 80u);
  EXPECT_EQ(entry.ms_since_last_vehicle_data, 27u);  // 7 ms old at send + 20 ms since arrival
  EXPECT_EQ(entry.missing_cameras, std::vector<std::string>{"rear"});
  EXPECT_EQ(entry.receiver_fault, (std::vector<std::string>{"CameraLost", "HighLatency"}));
  EXPECT_EQ(entry.vehicle_data, data);
  EXPECT_EQ(entry.last_remote_input, remote);
  EXPECT_EQ(entry.ack, (AckPair{18'446'744'073'709'551'615ULL, 4'294'967'295U}));
  EXPECT_TRUE(entry.sender_fault.empty());
}

TEST(Player, MissingVehicleDataAgeCountsFromLinkStart) {
  PlayerHarness harness;
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.start();
  harness.run_until(at_ms(340));
  EXPECT_EQ(harness.player.last_shared().vehicle_feedback.at("truck-1").ms_since_last_vehicle_data, 340u);
}

TEST(Player, PingEveryPeriodAndPongGivesLatency) {
  PlayerHarness harness;
  harness.pong_delay = Micros{37'000};
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.start();
  harness.run_until(SimTime{999'999});
  const auto pings = harness.pings("truck-1");
  ASSERT_EQ(pings.size(), 10u);
  EXPECT_EQ(pings[3].id, 3u);
  EXPECT_EQ(pings[3].sent_at, at_ms(300));
  EXPECT_EQ(harness.player.last_shared().vehicle_feedback.at("truck-1").ping_latency_ms, 37u);
  EXPECT_EQ(harness.player.stats().pongs_received, 10u);
}

TEST(Player, StalePongDoesNotOverwriteNewerLatency) {
  PlayerHarness harness;
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.start();
  harness.deliver_at(at_ms(120), "truck-1", LinkMessage{Pong{1, at_ms(100)}});
  harness.deliver_at(at_ms(125), "truck-1", LinkMessage{Pong{0, at_ms(0)}});  // reordered
  harness.run_until(at_ms(130));
  EXPECT_EQ(harness.player.last_shared().vehicle_feedback.at("truck-1").ping_latency_ms, 20u);
}

TEST(Player, UnknownVehicleInClientDataIsIgnoredWithWarning) {
  PlayerHarness harness;
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.start();
  ClientVehicleEntry ghost;
  ghost.user_data = RawJson{R"({"boo":1})"};
  ghost.ocp_disable_gamepad = true;
  ClientOcpShared data = client_entry("ghost", ghost);
  ClientVehicleEntry real;
  real.user_data = RawJson{R"({"mode":"dig"})"};
  data.client_user_data.emplace("truck-1", real);
  harness.client_data_at(at_ms(5), ClientSource::plugin, data);
  harness.run_until(at_ms(10));
  EXPECT_TRUE(harness.logged(LogLevel::warn, "ghost"));
  EXPECT_EQ(harness.player.stats().unknown_vehicle_entries, 1u);
  const auto control = harness.control_at("truck-1", at_ms(10));
  ASSERT_TRUE(control.has_value());
  EXPECT_EQ(control->client_user_data, RawJson{R"({"mode":"dig"})"});
  EXPECT_TRUE(control->controller.has_value());
  EXPECT_EQ(harness.player.last_shared().vehicle_feedback.count("ghost"), 0u);
}

TEST(Player, MessagesFromUnknownVehicleAreDropped) {
  PlayerHarness harness;
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.start();
  harness.video_at(at_ms(5), "nobody", AckPair{1, 2});
  harness.run_until(at_ms(10));
  EXPECT_TRUE(harness.logged(LogLevel::warn, "nobody"));
  EXPECT_EQ(harness.player.latest_sei("truck-1"), std::nullopt);
}

}  // namespace
}  // namespace ocp::testing
