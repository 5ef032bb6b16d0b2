// The Linux joystick reader (sim_app, the app layer: a device, so it is not part of player_core),
// driven through a FIFO that carries js_event records.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/joystick.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstdint>
#include <string>

#include "player/gamepad.hpp"
#include "sim_app/linux_joystick.hpp"

namespace ocp {
namespace {

using sim_app::LinuxJoystick;

SimTime ms(std::int64_t value) { return SimTime{value * 1000}; }

TEST(LinuxJoystick, MissingJoystickDeviceReportsAbsent) {
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
    if (directory == nullptr) {
      ADD_FAILURE() << "mkdtemp " << pattern << " failed";   // no device: the test's reader finds none
      return;
    }
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

TEST(LinuxJoystick, JoystickEventsMapToTheXpadLayoutAndAnUnplugReportsAbsent) {
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
