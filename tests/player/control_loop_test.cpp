// The Player frame loop: control message cadence, which controller each vehicle gets,
// operator-side faults InputLost and VehicleControlInactive, fleet and monitor links.
#include <gtest/gtest.h>

#include "player_harness.hpp"

namespace ocp::testing {
namespace {

Controller pressed_a() {
  Controller controller;
  controller.buttons.a = true;
  controller.axes.left_y = 0.75;
  return controller;
}

bool has_fault(const OperatorControl& control, FaultId id) {
  for (FaultId fault : control.sender_faults) {
    if (fault == id) return true;
  }
  return false;
}

TEST(Player, SendsOneHundredControlMessagesPerSecondAt100Hz) {
  PlayerHarness harness;
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.start();
  harness.run_until(SimTime{999'999});
  const auto controls = harness.controls("truck-1");
  ASSERT_EQ(controls.size(), 100u);
  for (std::size_t index = 0; index < controls.size(); ++index) {
    EXPECT_EQ(controls[index].first, at_ms(static_cast<std::int64_t>(index) * 10));
    EXPECT_EQ(controls[index].second.sequence, index);
  }
  EXPECT_EQ(harness.player.stats().control_messages_sent, 100u);
}

TEST(Player, FrameRateAbove100HzIsCapped) {
  PlayerConfig config;
  config.frame_rate_hz = 200.0;
  EXPECT_EQ(player_frame_period(config), Micros{10'000});
  PlayerHarness harness(config);
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.start();
  harness.run_until(SimTime{999'999});
  EXPECT_EQ(harness.controls("truck-1").size(), 100u);
  EXPECT_TRUE(harness.logged(LogLevel::warn, "capped"));
}

TEST(Player, LowerFrameRateSendsFewerMessages) {
  PlayerConfig config;
  config.frame_rate_hz = 30.0;
  EXPECT_EQ(player_frame_period(config), Micros{33'333});  // rounded to whole µs
  config.frame_rate_hz = 50.0;
  PlayerHarness harness(config);
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.start();
  harness.run_until(SimTime{999'999});
  const auto controls = harness.controls("truck-1");
  ASSERT_EQ(controls.size(), 50u);
  EXPECT_EQ(controls[1].first, at_ms(20));
}

TEST(Player, ActiveVehicleGetsTheGamepadSample) {
  PlayerHarness harness;
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.gamepad().set_constant(pressed_a());
  harness.player.start();
  harness.run_until(at_ms(50));
  const auto control = harness.control_at("truck-1", at_ms(50));
  ASSERT_TRUE(control.has_value());
  EXPECT_EQ(control->controller, pressed_a());
  EXPECT_TRUE(control->sender_faults.empty());
  EXPECT_EQ(harness.player.last_shared().last_input, pressed_a());
  EXPECT_EQ(harness.player.active_vehicle(), "truck-1");
}

TEST(Player, UnpluggedGamepadRaisesInputLostAndSendsSafeDefault) {
  PlayerHarness harness;
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.gamepad().set_constant(pressed_a());
  harness.player.start();
  harness.executor.call_at(at_ms(95), [&] { harness.player.gamepad().unplug(); });
  harness.executor.call_at(at_ms(205), [&] { harness.player.gamepad().replug(); });
  harness.run_until(at_ms(300));

  const auto before = harness.control_at("truck-1", at_ms(90));
  const auto unplugged = harness.control_at("truck-1", at_ms(100));
  const auto still = harness.control_at("truck-1", at_ms(200));
  const auto replugged = harness.control_at("truck-1", at_ms(210));
  ASSERT_TRUE(before && unplugged && still && replugged);
  EXPECT_FALSE(has_fault(*before, FaultId::InputLost));
  EXPECT_TRUE(has_fault(*unplugged, FaultId::InputLost));
  EXPECT_EQ(unplugged->controller, Controller::safe_default());
  EXPECT_TRUE(has_fault(*still, FaultId::InputLost));
  EXPECT_FALSE(has_fault(*replugged, FaultId::InputLost));
  EXPECT_EQ(replugged->controller, pressed_a());
  EXPECT_TRUE(harness.player.sender_faults("truck-1").empty());
}

TEST(Player, DisabledGamepadSendsNullControllerAndSuppressesInputLost) {
  PlayerHarness harness;
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.start();
  ClientVehicleEntry entry;
  entry.ocp_disable_gamepad = true;
  harness.client_data_at(at_ms(15), ClientSource::plugin, client_entry("truck-1", entry));
  harness.executor.call_at(at_ms(15), [&] { harness.player.gamepad().unplug(); });
  harness.run_until(at_ms(100));

  const auto control = harness.control_at("truck-1", at_ms(20));
  ASSERT_TRUE(control.has_value());
  EXPECT_EQ(control->controller, std::nullopt);
  EXPECT_FALSE(has_fault(*control, FaultId::InputLost));
  EXPECT_EQ(harness.player.last_shared().last_input, std::nullopt);

  // Re-enabling brings InputLost back while unplugged. (An entry with no field at all would be
  // a keep-alive, SPEC §4.2, and change nothing; the flag must be sent as false.)
  ClientVehicleEntry enable;
  enable.ocp_disable_gamepad = false;
  harness.player.handle_client_data(ClientSource::plugin, client_entry("truck-1", enable));
  harness.run_until(at_ms(110));
  const auto enabled = harness.control_at("truck-1", at_ms(110));
  ASSERT_TRUE(enabled.has_value());
  EXPECT_EQ(enabled->controller, Controller::safe_default());
  EXPECT_TRUE(has_fault(*enabled, FaultId::InputLost));
}

TEST(Player, SingleVehicleIsActiveWithoutSelection) {
  PlayerHarness harness;
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.start();
  harness.run_until(at_ms(0));
  EXPECT_FALSE(harness.player.sender_faults("truck-1").contains(FaultId::VehicleControlInactive));
}

TEST(Player, SingleVehicleNotSelectedIsInactive) {
  PlayerHarness harness;
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.gamepad().set_constant(pressed_a());
  harness.player.start();
  ClientOcpShared data;
  data.active_vehicle = "truck-9";
  harness.client_data_at(at_ms(5), ClientSource::tcp, data);
  harness.run_until(at_ms(10));
  const auto control = harness.control_at("truck-1", at_ms(10));
  ASSERT_TRUE(control.has_value());
  EXPECT_TRUE(has_fault(*control, FaultId::VehicleControlInactive));
  EXPECT_EQ(control->controller, Controller::safe_default());
  EXPECT_TRUE(harness.logged(LogLevel::warn, "truck-9"));
}

TEST(Player, FleetWithNoSelectionMakesEveryVehicleInactive) {
  PlayerConfig config;
  config.fleet = true;
  PlayerHarness harness(config);
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  ASSERT_TRUE(harness.add_vehicle("truck-2").ok());
  harness.player.gamepad().set_constant(pressed_a());
  harness.player.start();
  harness.run_until(at_ms(0));
  for (const char* name : {"truck-1", "truck-2"}) {
    const auto control = harness.control_at(name, at_ms(0));
    ASSERT_TRUE(control.has_value()) << name;
    EXPECT_TRUE(has_fault(*control, FaultId::VehicleControlInactive)) << name;
    EXPECT_EQ(control->controller, Controller::safe_default()) << name;
  }
  EXPECT_EQ(harness.player.active_vehicle(), std::nullopt);
  EXPECT_EQ(harness.player.last_shared().last_input, std::nullopt);

  ClientOcpShared select;
  select.active_vehicle = "truck-2";
  harness.client_data_at(at_ms(5), ClientSource::webview, select);
  harness.run_until(at_ms(10));
  const auto inactive = harness.control_at("truck-1", at_ms(10));
  const auto active = harness.control_at("truck-2", at_ms(10));
  ASSERT_TRUE(inactive && active);
  EXPECT_TRUE(has_fault(*inactive, FaultId::VehicleControlInactive));
  EXPECT_EQ(inactive->controller, Controller::safe_default());
  EXPECT_FALSE(has_fault(*active, FaultId::VehicleControlInactive));
  EXPECT_EQ(active->controller, pressed_a());
  EXPECT_EQ(harness.player.last_shared().last_input, pressed_a());
}

TEST(Player, StationSelectionDoesNotLockAClientSource) {
  PlayerConfig config;
  config.fleet = true;
  PlayerHarness harness(config);
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  ASSERT_TRUE(harness.add_vehicle("truck-2").ok());
  harness.player.gamepad().set_constant(pressed_a());
  harness.player.start();
  harness.executor.call_at(at_ms(5), [&] { harness.player.select_vehicle("truck-1"); });
  harness.run_until(at_ms(10));
  EXPECT_EQ(harness.control_at("truck-1", at_ms(10))->controller, pressed_a());
  EXPECT_EQ(harness.control_at("truck-2", at_ms(10))->controller, Controller::safe_default());
  EXPECT_EQ(harness.player.locked_source(), std::nullopt);
  harness.player.select_vehicle(std::nullopt);
  harness.run_until(at_ms(20));
  EXPECT_EQ(harness.player.active_vehicle(), std::nullopt);
  EXPECT_TRUE(harness.player.sender_faults("truck-1").contains(FaultId::VehicleControlInactive));
}

TEST(Player, SecondVehicleWithoutFleetIsAConfigurationError) {
  PlayerHarness harness;
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  const Status second = harness.add_vehicle("truck-2");
  ASSERT_FALSE(second.ok());
  EXPECT_NE(second.error().detail.find("fleet"), std::string::npos);
  EXPECT_NE(second.error().detail.find("truck-2"), std::string::npos);
  EXPECT_EQ(harness.player.vehicles(), std::vector<std::string>{"truck-1"});
}

TEST(Player, VehicleUnlinkedWhileStoppedIsGoneFromLaterFrames) {
  PlayerConfig config;
  config.fleet = true;
  PlayerHarness harness(config);
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  ASSERT_TRUE(harness.add_vehicle("truck-2").ok());
  harness.player.start();
  harness.run_until(at_ms(20));
  const Status while_running = harness.player.remove_vehicle("truck-1");
  ASSERT_FALSE(while_running.ok());
  EXPECT_EQ(while_running.error().detail, "cannot unlink vehicle 'truck-1' while the Player runs");
  harness.player.stop();

  ASSERT_TRUE(harness.player.remove_vehicle("truck-1").ok());
  const Status unknown = harness.player.remove_vehicle("truck-1");
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.error().detail, "vehicle 'truck-1' is not linked");
  EXPECT_EQ(harness.player.vehicles(), std::vector<std::string>{"truck-2"});
  const std::size_t truck_1_controls = harness.controls("truck-1").size();
  const std::size_t truck_2_controls = harness.controls("truck-2").size();
  ASSERT_GT(truck_1_controls, 0u);

  harness.player.start();
  harness.run_until(at_ms(60));
  EXPECT_EQ(harness.controls("truck-1").size(), truck_1_controls);
  EXPECT_GT(harness.controls("truck-2").size(), truck_2_controls);
  const VehicleOcpShared& shared = harness.player.last_shared();
  EXPECT_EQ(shared.vehicle_feedback.count("truck-1"), 0u) << "the unlinked vehicle's entry from the first run stayed";
  EXPECT_EQ(shared.vehicle_feedback.count("truck-2"), 1u);
}

TEST(Player, DuplicateVehicleNameIsRejected) {
  PlayerConfig config;
  config.fleet = true;
  PlayerHarness harness(config);
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  EXPECT_FALSE(harness.add_vehicle("truck-1").ok());
}

TEST(Player, MonitorLinkReceivesNoControl) {
  PlayerConfig config;
  config.fleet = true;
  PlayerHarness harness(config);
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  ASSERT_TRUE(harness.add_vehicle("watch", /*monitor=*/true).ok());
  harness.player.start();
  harness.run_until(at_ms(500));
  EXPECT_TRUE(harness.controls("watch").empty());
  EXPECT_EQ(harness.pings("watch").size(), 6u);  // 0, 100, …, 500 ms
  EXPECT_EQ(harness.controls("truck-1").size(), 51u);
  // The one control vehicle is active without a selection; the monitor never is.
  EXPECT_EQ(harness.player.active_vehicle(), "truck-1");
  const VehicleOcpShared& shared = harness.player.last_shared();
  ASSERT_EQ(shared.vehicle_feedback.size(), 2u);
  EXPECT_TRUE(shared.vehicle_feedback.at("watch").is_monitor);
  EXPECT_FALSE(shared.vehicle_feedback.at("truck-1").is_monitor);
  EXPECT_FALSE(harness.player.sender_faults("watch").contains(FaultId::VehicleControlInactive));
}

TEST(Player, StopEndsTheFrameLoop) {
  PlayerHarness harness;
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.start();
  harness.executor.call_at(at_ms(95), [&] { harness.player.stop(); });
  harness.run_until(at_ms(500));
  EXPECT_EQ(harness.controls("truck-1").size(), 10u);
  EXPECT_FALSE(harness.player.running());
}

}  // namespace
}  // namespace ocp::testing
