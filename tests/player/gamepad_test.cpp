// The scriptable gamepad: modes, waveform values, recorded playback and its text format.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/joystick.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>

#include "player/gamepad.hpp"
#include "player/linux_joystick.hpp"

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

TEST(Gamepad, RecordingFormatRoundTripsThroughAFile) {
  Recording recording;
  RecordedState first;
  first.controller.axes.left_x = -0.125;
  first.controller.buttons.dpad_left = true;
  RecordedState second;
  second.time = Micros{20'000};
  second.controller.axes.right_trigger = 1.0;
  recording.states = {first, second};
  const std::string path = ::testing::TempDir() + "player_gamepad_recording.txt";
  {
    std::ofstream file(path);
    file << format_recording(recording);
  }
  auto loaded = load_recording_file(path);
  std::remove(path.c_str());
  ASSERT_TRUE(loaded.ok()) << loaded.error().message();
  ASSERT_EQ(loaded->states.size(), 2u);
  EXPECT_EQ(loaded->states[0].controller, first.controller);
  EXPECT_EQ(loaded->states[1].time, second.time);
  EXPECT_EQ(loaded->states[1].controller, second.controller);
  EXPECT_FALSE(load_recording_file(path + ".missing").ok());
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

TEST(Gamepad, MissingJoystickDeviceReportsAbsent) {
  auto joystick = std::make_shared<LinuxJoystick>("/nonexistent/js9");
  EXPECT_FALSE(joystick->connected());
  Gamepad gamepad;
  gamepad.set_source(joystick->as_source());
  EXPECT_EQ(gamepad.sample(ms(0)), std::nullopt);
}

// The joystick API delivers whole js_event records; a FIFO carrying such records stands in for
// /dev/input/js0 (the reader cannot tell them apart: open, non-blocking read, EOF on unplug).
class FakeJoystickDevice {
 public:
  FakeJoystickDevice() {
    char pattern[] = "/tmp/ocp-js-XXXXXX";
    const char* directory = mkdtemp(pattern);
    EXPECT_NE(directory, nullptr);
    directory_ = directory;
    path_ = directory_ + "/js0";
    EXPECT_EQ(mkfifo(path_.c_str(), 0600), 0);
    // O_RDWR never blocks on a FIFO and keeps a writer present, so the reader sees no EOF yet.
    writer_ = ::open(path_.c_str(), O_RDWR | O_CLOEXEC);
    EXPECT_GE(writer_, 0);
  }
  ~FakeJoystickDevice() {
    unplug();
    ::unlink(path_.c_str());
    ::rmdir(directory_.c_str());
  }
  const std::string& path() const { return path_; }
  void send(std::uint8_t type, std::uint8_t number, std::int16_t value) {
    const js_event event{.time = 0, .value = value, .type = type, .number = number};
    EXPECT_EQ(::write(writer_, &event, sizeof(event)), static_cast<ssize_t>(sizeof(event)));
  }
  void unplug() {
    if (writer_ >= 0) ::close(writer_);
    writer_ = -1;
  }

 private:
  std::string directory_;
  std::string path_;
  int writer_ = -1;
};

TEST(Gamepad, JoystickEventsMapToTheXpadLayoutAndAnUnplugReportsAbsent) {
  FakeJoystickDevice device;
  auto joystick = std::make_shared<LinuxJoystick>(device.path());
  ASSERT_TRUE(joystick->connected());
  Gamepad gamepad;
  gamepad.set_source(joystick->as_source());
  EXPECT_EQ(gamepad.sample(ms(0)), Controller::safe_default());  // nothing pressed yet

  // The state the driver replays on open (JS_EVENT_INIT), then live events.
  device.send(JS_EVENT_AXIS | JS_EVENT_INIT, 0, -32767);
  device.send(JS_EVENT_BUTTON | JS_EVENT_INIT, 7, 1);
  device.send(JS_EVENT_AXIS, 5, 32767);
  device.send(JS_EVENT_AXIS, 1, 16384);
  device.send(JS_EVENT_AXIS, 7, -32767);
  device.send(JS_EVENT_BUTTON, 0, 1);
  device.send(JS_EVENT_BUTTON, 42, 1);  // not in the layout: ignored
  auto state = gamepad.sample(ms(10));
  ASSERT_TRUE(state.has_value());
  EXPECT_EQ(state->axes.left_x, -1.0);
  EXPECT_EQ(state->axes.right_trigger, 1.0);
  EXPECT_NEAR(state->axes.left_y, 16384.0 / 32767.0, 1e-12);
  EXPECT_TRUE(state->buttons.start);
  EXPECT_TRUE(state->buttons.a);
  EXPECT_TRUE(state->buttons.dpad_up);
  EXPECT_FALSE(state->buttons.dpad_down);
  EXPECT_FALSE(state->buttons.b);

  device.send(JS_EVENT_BUTTON, 0, 0);  // released
  device.send(JS_EVENT_AXIS, 7, 0);    // hat centred
  state = gamepad.sample(ms(20));
  ASSERT_TRUE(state.has_value());
  EXPECT_FALSE(state->buttons.a);
  EXPECT_FALSE(state->buttons.dpad_up);
  EXPECT_TRUE(state->buttons.start);  // unchanged buttons keep their state

  device.unplug();
  EXPECT_EQ(gamepad.sample(ms(30)), std::nullopt);
  EXPECT_FALSE(joystick->connected());
}

}  // namespace
}  // namespace ocp
