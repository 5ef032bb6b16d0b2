// The safety layer on its own: every rule, at exact microsecond times.
#include "vehicle_client/safety_layer.hpp"

#include <gtest/gtest.h>

#include "inputs.hpp"

namespace ocp {
namespace {

using testing::ms;
using testing::start_pressed;

OcpControlMessage message_with(std::optional<Controller> controller, bool fault = false) {
  OcpControlMessage message;
  message.controller = controller;
  message.telemetry.fault = fault;
  return message;
}

OcpControlMessage user_data_message(std::string json) {
  OcpControlMessage message;
  message.controller = std::nullopt;
  message.client_user_data = RawJson{std::move(json)};
  return message;
}

Controller driving(double throttle_raw, double left_x = 0.0, double brake_raw = -1.0) {
  Controller controller;
  controller.axes.right_trigger = throttle_raw;
  controller.axes.left_trigger = brake_raw;
  controller.axes.left_x = left_x;
  return controller;
}

// The idle gamepad IS the default controller (which means "brake"); a barely touched throttle
// trigger is the smallest live command.
Controller coasting() { return driving(-0.98); }

// Rate and magnitude tests look at one message over seconds: keep the watchdog out of them.
SafetyConfig relaxed() {
  SafetyConfig config;
  config.watchdog = Micros{60'000'000};
  return config;
}

// A layer that was enabled at t = 0 with neutral sticks.
SafetyLayer enabled_layer(SafetyConfig config = relaxed()) {
  SafetyLayer layer(config);
  layer.on_control_message(message_with(start_pressed()), ms(0));
  layer.evaluate(ms(0));
  return layer;
}

TEST(SafetyLayer, StartsDisabledInTheSafeStateWithTheSafeBrakeApplied) {
  SafetyConfig config;
  config.safe_brake = 0.8;
  SafetyLayer layer(config);
  const SafetyOutput& output = layer.evaluate(ms(0));
  EXPECT_TRUE(output.safe_state);
  EXPECT_EQ(output.drive_state, DriveState::disabled);
  EXPECT_TRUE(output.reasons.contains(SafetyReason::no_control_message));
  EXPECT_TRUE(output.reasons.contains(SafetyReason::drive_disabled));
  EXPECT_EQ(output.command, (ActuatorCommand{0.0, 0.8, 0.0}));
}

TEST(SafetyLayer, WatchdogFiresExactlyWhenTheLastMessageIsWatchdogOld) {
  SafetyConfig config;
  config.watchdog = ms(300);
  SafetyLayer layer = enabled_layer(config);
  layer.on_control_message(message_with(coasting()), ms(100));
  EXPECT_FALSE(layer.evaluate(ms(400) - Micros{1}).reasons.contains(SafetyReason::command_timeout));
  EXPECT_FALSE(layer.output().safe_state);
  const SafetyOutput& output = layer.evaluate(ms(400));
  EXPECT_TRUE(output.reasons.contains(SafetyReason::command_timeout));
  EXPECT_TRUE(output.safe_state);
}

TEST(SafetyLayer, FreshMessagesKeepTheWatchdogQuiet) {
  SafetyConfig config;
  config.watchdog = ms(300);
  SafetyLayer layer = enabled_layer(config);
  for (int tick = 1; tick <= 100; ++tick) {
    layer.on_control_message(message_with(coasting()), ms(10 * tick));
    EXPECT_FALSE(layer.evaluate(ms(10 * tick) + ms(5)).safe_state) << "tick " << tick;
  }
}

TEST(SafetyLayer, WatchdogTimeoutLatchesTheDriveStateOff) {
  SafetyConfig config;
  config.watchdog = ms(300);
  SafetyLayer layer = enabled_layer(config);
  layer.evaluate(ms(300));
  EXPECT_EQ(layer.output().drive_state, DriveState::disabled);
  // Messages resume, but nobody pressed start again: stays disabled.
  layer.on_control_message(message_with(coasting()), ms(310));
  const SafetyOutput& output = layer.evaluate(ms(310));
  EXPECT_EQ(output.drive_state, DriveState::disabled);
  EXPECT_FALSE(output.reasons.contains(SafetyReason::command_timeout));
  EXPECT_TRUE(output.reasons.contains(SafetyReason::drive_disabled));
}

TEST(SafetyLayer, TelemetryFaultForcesTheSafeStateAndDisables) {
  SafetyLayer layer = enabled_layer();
  layer.on_control_message(message_with(driving(1.0), /*fault=*/true), ms(10));
  const SafetyOutput& output = layer.evaluate(ms(10));
  EXPECT_TRUE(output.safe_state);
  EXPECT_TRUE(output.reasons.contains(SafetyReason::telemetry_fault));
  EXPECT_EQ(output.drive_state, DriveState::disabled);
  EXPECT_EQ(output.command.throttle, 0.0);
}

TEST(SafetyLayer, DecidesOnTheFaultFlagNeverOnTheDisplayString) {
  SafetyLayer layer = enabled_layer();
  OcpControlMessage message = message_with(coasting());
  message.telemetry.fault_reason = "High Latency";  // text without the flag: not a fault
  layer.on_control_message(message, ms(10));
  EXPECT_FALSE(layer.evaluate(ms(10)).reasons.contains(SafetyReason::telemetry_fault));
  message.telemetry.fault = true;
  message.telemetry.fault_reason = "";  // flag without text: a fault
  layer.on_control_message(message, ms(20));
  EXPECT_TRUE(layer.evaluate(ms(20)).reasons.contains(SafetyReason::telemetry_fault));
}

TEST(SafetyLayer, DefaultControllerMeansSafeStateButKeepsDriveEnabled) {
  SafetyLayer layer = enabled_layer();
  layer.on_control_message(message_with(Controller::safe_default()), ms(10));
  const SafetyOutput& output = layer.evaluate(ms(10));
  EXPECT_TRUE(output.safe_state);
  EXPECT_TRUE(output.reasons.contains(SafetyReason::default_controller));
  EXPECT_EQ(output.drive_state, DriveState::enabled);
  layer.on_control_message(message_with(driving(0.0)), ms(20));
  EXPECT_FALSE(layer.evaluate(ms(20)).safe_state);
}

TEST(SafetyLayer, StartPressWithNeutralSticksEnables) {
  SafetyLayer layer;
  layer.on_control_message(message_with(start_pressed()), ms(0));
  const SafetyOutput& output = layer.evaluate(ms(0));
  EXPECT_EQ(output.drive_state, DriveState::enabled);
  EXPECT_FALSE(output.safe_state);
}

TEST(SafetyLayer, EnableIsRefusedWithADeflectedStick) {
  SafetyLayer layer;
  Controller controller = start_pressed();
  controller.axes.left_x = 0.5;
  layer.on_control_message(message_with(controller), ms(0));
  EXPECT_EQ(layer.evaluate(ms(0)).drive_state, DriveState::disabled);
}

TEST(SafetyLayer, EnableIsRefusedWithAPressedTrigger) {
  SafetyLayer layer;
  Controller controller = start_pressed();
  controller.axes.right_trigger = 0.0;  // half throttle
  layer.on_control_message(message_with(controller), ms(0));
  EXPECT_EQ(layer.evaluate(ms(0)).drive_state, DriveState::disabled);
}

TEST(SafetyLayer, EnableIsRefusedWhileAFaultIsReported) {
  SafetyLayer layer;
  layer.on_control_message(message_with(start_pressed(), /*fault=*/true), ms(0));
  EXPECT_EQ(layer.evaluate(ms(0)).drive_state, DriveState::disabled);
}

TEST(SafetyLayer, EnableNeedsAFreshPressNotAHeldButton) {
  SafetyLayer layer = enabled_layer();
  Controller back = start_pressed();
  back.buttons.back = true;
  layer.on_control_message(message_with(back), ms(10));  // back disables although start is held
  EXPECT_EQ(layer.evaluate(ms(10)).drive_state, DriveState::disabled);
  layer.on_control_message(message_with(start_pressed()), ms(20));  // still held: no new press
  EXPECT_EQ(layer.evaluate(ms(20)).drive_state, DriveState::disabled);
  layer.on_control_message(message_with(Controller{}), ms(30));  // released
  layer.on_control_message(message_with(start_pressed()), ms(40));  // pressed again
  EXPECT_EQ(layer.evaluate(ms(40)).drive_state, DriveState::enabled);
}

TEST(SafetyLayer, BackButtonDisables) {
  SafetyLayer layer = enabled_layer();
  Controller controller;
  controller.buttons.back = true;
  layer.on_control_message(message_with(controller), ms(10));
  const SafetyOutput& output = layer.evaluate(ms(10));
  EXPECT_EQ(output.drive_state, DriveState::disabled);
  EXPECT_TRUE(output.safe_state);
}

TEST(SafetyLayer, ThrottleRisesAtItsRateAndStopsAtItsCap) {
  SafetyConfig config = relaxed();
  config.throttle_rate_per_s = 2.0;
  config.max_throttle = 0.5;
  SafetyLayer layer = enabled_layer(config);
  layer.on_control_message(message_with(driving(1.0)), ms(0));
  EXPECT_DOUBLE_EQ(layer.evaluate(ms(100)).command.throttle, 0.2);
  EXPECT_DOUBLE_EQ(layer.evaluate(ms(200)).command.throttle, 0.4);
  EXPECT_DOUBLE_EQ(layer.evaluate(ms(300)).command.throttle, 0.5);
  EXPECT_DOUBLE_EQ(layer.output().requested.throttle, 1.0);
}

TEST(SafetyLayer, BrakeReleasesAtItsRate) {
  SafetyConfig config = relaxed();
  config.brake_rate_per_s = 5.0;
  SafetyLayer layer = enabled_layer(config);
  layer.on_control_message(message_with(coasting()), ms(0));
  EXPECT_DOUBLE_EQ(layer.evaluate(ms(100)).command.brake, 0.5);
  EXPECT_DOUBLE_EQ(layer.evaluate(ms(200)).command.brake, 0.0);
}

TEST(SafetyLayer, SteeringMovesAtItsRateBothWaysAndStopsAtItsCap) {
  SafetyConfig config = relaxed();
  config.steer_rate_per_s = 1.0;
  config.max_steer = 0.3;
  SafetyLayer layer = enabled_layer(config);
  layer.on_control_message(message_with(driving(-1.0, /*left_x=*/-1.0)), ms(0));  // full left
  EXPECT_DOUBLE_EQ(layer.evaluate(ms(100)).command.steer, 0.1);
  EXPECT_DOUBLE_EQ(layer.evaluate(ms(1000)).command.steer, 0.3);
  layer.on_control_message(message_with(driving(-1.0, /*left_x=*/1.0)), ms(1000));  // full right
  EXPECT_DOUBLE_EQ(layer.evaluate(ms(1200)).command.steer, 0.1);
  EXPECT_DOUBLE_EQ(layer.evaluate(ms(2000)).command.steer, -0.3);
}

TEST(SafetyLayer, SafeStateCutsThrottleAtOnceRampsTheBrakeAndHoldsSteering) {
  SafetyConfig config = relaxed();
  config.brake_rate_per_s = 5.0;
  config.safe_brake = 1.0;
  SafetyLayer layer = enabled_layer(config);
  layer.on_control_message(message_with(driving(1.0, -0.5)), ms(0));
  layer.evaluate(ms(1000));
  ASSERT_DOUBLE_EQ(layer.output().command.throttle, 1.0);
  ASSERT_DOUBLE_EQ(layer.output().command.brake, 0.0);
  const double steer = layer.output().command.steer;
  layer.on_control_message(message_with(Controller::safe_default(), /*fault=*/true), ms(1000));
  const SafetyOutput& output = layer.evaluate(ms(1100));
  EXPECT_EQ(output.command.throttle, 0.0);
  EXPECT_DOUBLE_EQ(output.command.brake, 0.5);
  EXPECT_DOUBLE_EQ(output.command.steer, steer);
  EXPECT_DOUBLE_EQ(layer.evaluate(ms(1200)).command.brake, 1.0);
}

TEST(SafetyLayer, BrakeRequestOverridesThrottle) {
  SafetyLayer layer = enabled_layer();
  layer.on_control_message(message_with(driving(1.0, 0.0, /*brake_raw=*/0.0)), ms(0));
  const SafetyOutput& output = layer.evaluate(ms(500));
  EXPECT_EQ(output.command.throttle, 0.0);
  EXPECT_DOUBLE_EQ(output.command.brake, 0.5);
}

TEST(SafetyLayer, NullControllerTakesCommandsFromClientUserData) {
  SafetyLayer layer;
  layer.on_control_message(user_data_message(R"({"throttle":0,"enable":true})"), ms(0));
  ASSERT_EQ(layer.evaluate(ms(0)).drive_state, DriveState::enabled);
  layer.on_control_message(user_data_message(R"({"throttle":0.4,"steer":0.25,"mode":"manual"})"), ms(10));
  const SafetyOutput& output = layer.evaluate(ms(10));
  EXPECT_FALSE(output.safe_state);
  EXPECT_DOUBLE_EQ(output.requested.throttle, 0.4);
  EXPECT_DOUBLE_EQ(output.requested.steer, 0.25);
}

TEST(SafetyLayer, NullControllerWithoutCommandsIsSafeAndCannotEnable) {
  SafetyLayer layer;
  layer.on_control_message(user_data_message(R"({"mode":"manual"})"), ms(0));
  const SafetyOutput& output = layer.evaluate(ms(0));
  EXPECT_TRUE(output.safe_state);
  EXPECT_TRUE(output.reasons.contains(SafetyReason::no_command_source));
  OcpControlMessage bare = message_with(std::nullopt);
  layer.on_control_message(bare, ms(10));
  EXPECT_TRUE(layer.evaluate(ms(10)).reasons.contains(SafetyReason::no_command_source));
}

TEST(SafetyLayer, UserDataEnableFalseDisables) {
  SafetyLayer layer;
  layer.on_control_message(user_data_message(R"({"steer":0,"enable":true})"), ms(0));
  ASSERT_EQ(layer.evaluate(ms(0)).drive_state, DriveState::enabled);
  layer.on_control_message(user_data_message(R"({"steer":0,"enable":false})"), ms(10));
  EXPECT_EQ(layer.evaluate(ms(10)).drive_state, DriveState::disabled);
}

TEST(SafetyLayer, ResetDisablesButKeepsActuatorPositions) {
  SafetyLayer layer = enabled_layer();
  layer.on_control_message(message_with(driving(1.0)), ms(0));
  layer.evaluate(ms(200));
  const ActuatorCommand before = layer.output().command;
  layer.reset(ms(200));
  EXPECT_EQ(layer.output().command, before);
  const SafetyOutput& output = layer.evaluate(ms(200));
  EXPECT_EQ(output.drive_state, DriveState::disabled);
  EXPECT_TRUE(output.reasons.contains(SafetyReason::no_control_message));
  EXPECT_EQ(output.command.throttle, 0.0);
}

TEST(SafetyLayer, ParsesUserDataCommandsStrictly) {
  EXPECT_FALSE(parse_user_data_command("[1,2]"));
  EXPECT_FALSE(parse_user_data_command("{\"throttle\":\"fast\"}"));
  EXPECT_FALSE(parse_user_data_command("{not json"));
  EXPECT_FALSE(parse_user_data_command("{\"mode\":\"manual\"}"));
  const std::optional<UserDataCommand> command = parse_user_data_command(R"({"brake":1,"enable":false})");
  ASSERT_TRUE(command);
  EXPECT_EQ(command->brake, 1.0);
  EXPECT_EQ(command->enable, false);
  EXPECT_FALSE(command->throttle);
}

TEST(SafetyLayer, MapsTheGamepadToNormalisedCommands) {
  const ActuatorCommand command = command_from_controller(driving(0.0, 0.5, 1.0));
  EXPECT_DOUBLE_EQ(command.throttle, 0.5);
  EXPECT_DOUBLE_EQ(command.brake, 1.0);
  EXPECT_DOUBLE_EQ(command.steer, -0.5);  // stick right = right turn = negative
  EXPECT_TRUE(sticks_neutral(Controller{}, 0.05));
  EXPECT_FALSE(sticks_neutral(driving(-1.0, 0.0, -0.8), 0.05));
}

TEST(SafetyLayer, RejectsUnusableConfigs) {
  EXPECT_FALSE(validate(SafetyConfig{}));
  SafetyConfig config;
  config.watchdog = Micros{0};
  EXPECT_TRUE(validate(config));
  config = {};
  config.max_throttle = 1.5;
  EXPECT_TRUE(validate(config));
  config = {};
  config.steer_rate_per_s = 0.0;
  EXPECT_TRUE(validate(config));
  config = {};
  config.safe_brake = 0.0;
  EXPECT_TRUE(validate(config));
}

TEST(SafetyLayer, NamesEveryReason) {
  SafetyReasons reasons;
  for (std::size_t index = 0; index < safety_reason_count; ++index) reasons.set(static_cast<SafetyReason>(index), true);
  const std::vector<std::string_view> names = reasons.names();
  ASSERT_EQ(names.size(), safety_reason_count);
  EXPECT_EQ(names.front(), "no_control_message");
  EXPECT_EQ(names.back(), "drive_disabled");
}

}  // namespace
}  // namespace ocp
