// Operator-side configurations seen end to end: client data source locking (SPEC §4.3), a
// fleet with active_vehicle (§7) and a monitor link.
#include <gtest/gtest.h>

#include <algorithm>

#include "world_fixture.hpp"

namespace ocp::world_test {
namespace {

ClientOcpShared user_data_for(const std::string& vehicle, const std::string& json) {
  ClientOcpShared data;
  data.client_user_data[vehicle].user_data = RawJson{json};
  return data;
}

TEST(WorldClientData, WebViewUserDataReachesTheVehicleAndKeepsTheLoopClosed) {
  VirtualWorld sim(one_vehicle_config());
  ASSERT_TRUE(sim.start());
  PlayerCore& player = sim.world().player();
  // A web view that sends every Player frame: the Player injects the latest SEI pair.
  PeriodicTimer web_view(sim.executor(), tick, [&](SimTime) {
    player.handle_client_data(ClientSource::webview, user_data_for("truck-1", R"({"mode":"manual"})"));
  });
  web_view.start(SimTime{Micros{5'000}});
  sim.run_for(Millis{1000});

  const StreamTap* tap = sim.world().vehicle_tap("truck-1");
  ASSERT_TRUE(tap->last_control()->client_user_data.has_value());
  EXPECT_NE(tap->last_control()->client_user_data->text.find("manual"), std::string::npos);
  EXPECT_EQ(player.locked_source(), ClientSource::webview);
  EXPECT_TRUE(sim.world().streamer("truck-1").faults().empty())
      << sim.world().streamer("truck-1").faults().fault_reason();
}

TEST(WorldClientData, SecondSourceStopsAllClientDataAndTheLoopBreaksVisibly) {
  VirtualWorld sim(one_vehicle_config());
  ASSERT_TRUE(sim.start());
  PlayerCore& player = sim.world().player();
  PeriodicTimer web_view(sim.executor(), tick, [&](SimTime) {
    player.handle_client_data(ClientSource::webview, user_data_for("truck-1", R"({"mode":"manual"})"));
  });
  web_view.start(SimTime{Micros{5'000}});
  sim.run_for(Millis{1000});
  StreamerCore& streamer = sim.world().streamer("truck-1");
  ASSERT_TRUE(streamer.faults().empty());

  // A plugin starts sending too (with a perfectly valid pair): conflict.
  ClientOcpShared plugin_data = user_data_for("truck-1", R"({"mode":"plugin"})");
  const auto sei = player.latest_sei("truck-1");
  ASSERT_TRUE(sei.has_value());
  plugin_data.client_user_data["truck-1"].ack_time_returned = sei->ack_time;
  plugin_data.client_user_data["truck-1"].ack_time_mac_returned = sei->ack_time_mac;
  player.handle_client_data(ClientSource::plugin, plugin_data);
  EXPECT_TRUE(player.client_data_stopped());
  EXPECT_EQ(player.stats().source_conflicts, 1u);

  // No echo from anyone (no fallback to self-echo): the Streamer sees the loop open.
  ASSERT_TRUE(sim.run_until_condition([&] { return streamer.faults().contains(FaultId::InvalidMac); },
                                      Millis{100}));
  sim.run_for(Millis{500});
  EXPECT_TRUE(streamer.faults().contains(FaultId::InvalidMac));
  const StreamTap* tap = sim.world().vehicle_tap("truck-1");
  EXPECT_FALSE(tap->last_control()->client_user_data.has_value()) << "user data must stop too";
  EXPECT_NE(tap->last_control()->telemetry.fault_reason.find("Latency Loop Not Closed"), std::string::npos);
  EXPECT_TRUE(sim.world().vehicle_client("truck-1")->safety().safe_state);
  EXPECT_FALSE(sim.log().lines_containing(" player ERROR: ").empty()) << "the conflict is logged as an error";
}

// Active vehicle selection by a web view that sends every frame.
struct FleetSim {
  explicit FleetSim(std::optional<std::string> active) : sim(make_config()) {
    EXPECT_TRUE(sim.start());
    sim.world().player().gamepad().set_constant(driving_controller());
    if (active) {
      web_view = std::make_unique<PeriodicTimer>(sim.executor(), tick, [this, active](SimTime) {
        ClientOcpShared data;
        data.active_vehicle = active;
        sim.world().player().handle_client_data(ClientSource::webview, data);
      });
      web_view->start(SimTime{Micros{5'000}});
    }
  }
  static WorldConfig make_config() {
    WorldConfig config = one_vehicle_config();
    config.player.fleet = true;
    config.vehicles = {vehicle_spec("alpha"), vehicle_spec("bravo"), vehicle_spec("charlie")};
    return config;
  }
  VirtualWorld sim;
  std::unique_ptr<PeriodicTimer> web_view;
};

TEST(WorldFleet, OnlyTheActiveVehicleGetsTheGamepadAndTheOthersAreInactive) {
  FleetSim fleet("bravo");
  fleet.sim.run_for(Millis{1000});
  World& world = fleet.sim.world();
  EXPECT_EQ(world.player().active_vehicle(), "bravo");

  EXPECT_TRUE(world.player().sender_faults("bravo").empty());
  EXPECT_TRUE(world.streamer("bravo").faults().empty()) << world.streamer("bravo").faults().fault_reason();
  EXPECT_EQ(world.vehicle_tap("bravo")->last_control()->controller, driving_controller());
  for (const std::string name : {"alpha", "charlie"}) {
    SCOPED_TRACE(name);
    EXPECT_TRUE(world.player().sender_faults(name).contains(FaultId::VehicleControlInactive));
    // The operator fault reaches the Streamer as OperatorStationHasError (control path).
    EXPECT_TRUE(world.streamer(name).faults().contains(FaultId::OperatorStationHasError));
    EXPECT_EQ(world.vehicle_tap(name)->last_control()->controller, Controller::safe_default());
    const auto& sender = world.player().last_shared().vehicle_feedback.at(name).sender_fault;
    EXPECT_NE(std::find(sender.begin(), sender.end(), "VehicleControlInactive"), sender.end());
  }
  EXPECT_EQ(world.player().last_shared().vehicle_feedback.size(), 3u);
}

TEST(WorldFleet, WithoutASelectionEveryVehicleIsInactive) {
  FleetSim fleet(std::nullopt);
  fleet.sim.run_for(Millis{500});
  World& world = fleet.sim.world();
  EXPECT_FALSE(world.player().active_vehicle().has_value());
  for (const std::string name : {"alpha", "bravo", "charlie"}) {
    SCOPED_TRACE(name);
    EXPECT_TRUE(world.player().sender_faults(name).contains(FaultId::VehicleControlInactive));
    EXPECT_EQ(world.vehicle_tap(name)->last_control()->controller, Controller::safe_default());
  }
}

TEST(WorldFleet, EachVehicleHasItsOwnLatencyLoop) {
  WorldConfig config = FleetSim::make_config();
  config.vehicles[0].to_player = delay_of(Millis{100});
  config.vehicles[2].to_player = delay_of(Millis{200});
  VirtualWorld sim(config);
  ASSERT_TRUE(sim.start());
  sim.run_for(Millis{2000});
  const auto alpha = *sim.world().streamer("alpha").latency_ms();
  const auto bravo = *sim.world().streamer("bravo").latency_ms();
  const auto charlie = *sim.world().streamer("charlie").latency_ms();
  EXPECT_GE(alpha, 100u);
  EXPECT_LT(bravo, 100u);
  EXPECT_GE(charlie, 200u);
  for (const std::string name : {"alpha", "bravo", "charlie"}) {
    EXPECT_FALSE(sim.world().streamer(name).faults().contains(FaultId::InvalidMac)) << name;
  }
}

TEST(WorldMonitor, MonitorLinkReceivesFeedbackButSendsNoControl) {
  WorldConfig config = one_vehicle_config();
  config.vehicles[0].monitor = true;
  VirtualWorld sim(config);
  ASSERT_TRUE(sim.start());
  sim.run_for(Millis{1500});

  const VehicleFeedback& feedback = sim.world().player().last_shared().vehicle_feedback.at("truck-1");
  EXPECT_TRUE(feedback.is_monitor);
  EXPECT_TRUE(feedback.vehicle_data.has_value()) << "vehicle data still flows to a monitor";
  EXPECT_FALSE(sim.world().player().sender_faults("truck-1").contains(FaultId::NoFeedbackMessage));
  EXPECT_EQ(sim.world().streamer("truck-1").stats().operator_messages_received, 0u);
  // Nobody controls this vehicle: its Streamer says so, and it stays safe.
  EXPECT_TRUE(sim.world().streamer("truck-1").faults().contains(FaultId::NoControlMessage));
  EXPECT_TRUE(sim.world().vehicle_client("truck-1")->safety().safe_state);
}

}  // namespace
}  // namespace ocp::world_test
