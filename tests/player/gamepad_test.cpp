// The scriptable gamepad: modes, waveform values, recorded playback and its text format.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>

#include "player/gamepad.hpp"

namespace ocp {
namespace {

SimTime ms(std::int64_t value) { return SimTime{value * 1000}; }

TEST(Gamepad, IdleIsConnectedAndNeutral) {
  Gamepad gamepad;
  EXPECT_TRUE(gamepad.plugged());
  EXPECT_EQ(gamepad.mode(), Gamepad::Mode::idle);
  EXPECT_EQ(gamepad.sample(ms(123)), Controller::safe_default());
}

TEST(Gamepad, ConstantReturnsTheGivenController) {
  Gamepad gamepad;
  Controller controller;
  controller.buttons.a = true;
  controller.axes.left_y = 0.25;
  gamepad.set_constant(controller);
  EXPECT_EQ(gamepad.sample(ms(0)), controller);
  EXPECT_EQ(gamepad.sample(ms(999'999)), controller);
}

TEST(Gamepad, UnplugGivesNoSampleUntilReplug) {
  Gamepad gamepad;
  gamepad.unplug();
  EXPECT_FALSE(gamepad.plugged());
  EXPECT_EQ(gamepad.sample(ms(10)), std::nullopt);
  gamepad.replug();
  EXPECT_EQ(gamepad.sample(ms(20)), Controller::safe_default());
}

TEST(Gamepad, WaveformFollowsSineOnChosenAxis) {
  Gamepad gamepad;
  Waveform waveform;
  waveform.waves.push_back(SineWave{GamepadAxis::left_x, 0.5, Micros{1'000'000}, 0.0});
  waveform.base.buttons.b = true;
  gamepad.set_waveform(waveform, ms(100));
  EXPECT_NEAR(gamepad.sample(ms(100))->axes.left_x, 0.0, 1e-12);
  EXPECT_NEAR(gamepad.sample(ms(350))->axes.left_x, 0.5, 1e-12);   // quarter period
  EXPECT_NEAR(gamepad.sample(ms(850))->axes.left_x, -0.5, 1e-12);  // three quarters
  EXPECT_TRUE(gamepad.sample(ms(850))->buttons.b);
  EXPECT_EQ(gamepad.sample(ms(350))->axes.left_trigger, -1.0);     // undriven axis keeps base
}

TEST(Gamepad, WaveformIsClampedToUnitRange) {
  Gamepad gamepad;
  Waveform waveform;
  waveform.base.axes.right_trigger = 0.5;
  waveform.waves.push_back(SineWave{GamepadAxis::right_trigger, 1.0, Micros{400'000}, 0.0});
  gamepad.set_waveform(waveform);
  EXPECT_EQ(gamepad.sample(ms(100))->axes.right_trigger, 1.0);
}

TEST(Gamepad, RecordingHoldsEachStateUntilTheNext) {
  auto recording = parse_recording(
      "# a comment\n"
      "0 left_y=0.5 a=1\n"
      "\n"
      "500 left_y=-0.25 right_trigger=0.2   # trailing comment\n"
      "1000\n");
  ASSERT_TRUE(recording.ok()) << recording.error().message();
  ASSERT_EQ(recording->states.size(), 3u);
  Gamepad gamepad;
  gamepad.set_recording(*recording, ms(1000));
  EXPECT_EQ(gamepad.sample(ms(999)), Controller::safe_default());  // before playback starts
  EXPECT_EQ(gamepad.sample(ms(1000))->axes.left_y, 0.5);
  EXPECT_TRUE(gamepad.sample(ms(1499))->buttons.a);
  EXPECT_EQ(gamepad.sample(ms(1500))->axes.left_y, -0.25);
  EXPECT_FALSE(gamepad.sample(ms(1500))->buttons.a);
  EXPECT_EQ(gamepad.sample(ms(1500))->axes.right_trigger, 0.2);
  EXPECT_EQ(gamepad.sample(ms(2000)), Controller::safe_default());  // last line: neutral
  EXPECT_EQ(gamepad.sample(ms(9000)), Controller::safe_default());  // no loop: holds
}

TEST(Gamepad, RecordingLoopsWithTheLastTimeAsPeriod) {
  auto recording = parse_recording("0 x=1\n500 y=1\n1000\n");
  ASSERT_TRUE(recording.ok());
  Gamepad gamepad;
  gamepad.set_recording(*recording, ms(0), true);
  EXPECT_TRUE(gamepad.sample(ms(2100))->buttons.x);
  EXPECT_TRUE(gamepad.sample(ms(2600))->buttons.y);
  EXPECT_TRUE(gamepad.sample(ms(3000))->buttons.x);
}

TEST(Gamepad, RecordingErrorsNameTheLine) {
  auto unknown = parse_recording("0 a=1\n10 turbo=1\n");
  ASSERT_FALSE(unknown.ok());
  EXPECT_NE(unknown.error().detail.find("line 2"), std::string::npos);
  EXPECT_NE(unknown.error().detail.find("turbo"), std::string::npos);
  EXPECT_FALSE(parse_recording("0 left_x=1.5\n").ok());
  EXPECT_FALSE(parse_recording("0 a=2\n").ok());
  EXPECT_FALSE(parse_recording("100\n50\n").ok());
  EXPECT_FALSE(parse_recording("-5 a=1\n").ok());
  EXPECT_FALSE(parse_recording("abc\n").ok());
}

TEST(Gamepad, RecordingFormatRoundTripsThroughItsText) {
  Recording recording;
  RecordedState first;
  first.controller.axes.left_x = -0.125;
  first.controller.buttons.dpad_left = true;
  RecordedState second;
  second.time = Micros{20'000};
  second.controller.axes.right_trigger = 1.0;
  recording.states = {first, second};
  auto loaded = parse_recording(format_recording(recording));
  ASSERT_TRUE(loaded.ok()) << loaded.error().message();
  ASSERT_EQ(loaded->states.size(), 2u);
  EXPECT_EQ(loaded->states[0].controller, first.controller);
  EXPECT_EQ(loaded->states[1].time, second.time);
  EXPECT_EQ(loaded->states[1].controller, second.controller);
}

TEST(Gamepad, ExternalSourceIsAskedAndItsAbsenceMeansUnplugged) {
  Gamepad gamepad;
  bool present = true;
  gamepad.set_source([&present](SimTime now) -> std::optional<Controller> {
    if (!present) return std::nullopt;
    Controller controller;
    controller.axes.left_x = static_cast<double>(now.count()) / 1e6;
    return controller;
  });
  EXPECT_EQ(gamepad.mode(), Gamepad::Mode::external);
  EXPECT_EQ(gamepad.sample(ms(250))->axes.left_x, 0.25);
  present = false;
  EXPECT_EQ(gamepad.sample(ms(260)), std::nullopt);
}

}  // namespace
}  // namespace ocp
