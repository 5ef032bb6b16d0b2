#pragma once
// A real Linux joystick (/dev/input/js*, the joystick API of <linux/joystick.h>) read without
// blocking, mapped to an OCP Controller with the xpad (Xbox-style) layout:
//   axes    0 left_x, 1 left_y, 2 left_trigger, 3 right_x, 4 right_y, 5 right_trigger,
//           6/7 the d-pad hat (reported as dpad_left/right/up/down buttons)
//   buttons 0 a, 1 b, 2 x, 3 y, 4 left_bumper, 5 right_bumper, 6 back, 7 start, 8 guide,
//           9 left_thumb, 10 right_thumb
// Values are raw, scaled from [-32767, 32767] to [-1, 1]. Real time only (a device is not
// virtual); plug into a Gamepad with `gamepad.set_source(joystick->as_source())`.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "ocp/messages.hpp"
#include "player/gamepad.hpp"

namespace ocp::sim_app {

class LinuxJoystick : public std::enable_shared_from_this<LinuxJoystick> {
 public:
  explicit LinuxJoystick(std::string path = "/dev/input/js0");
  ~LinuxJoystick();
  LinuxJoystick(const LinuxJoystick&) = delete;
  LinuxJoystick& operator=(const LinuxJoystick&) = delete;

  // Drains every pending event and returns the current state; nullopt while the device is
  // absent. A vanished device is reopened every `reopen_interval_polls` polls.
  std::optional<Controller> poll();
  bool connected() const { return descriptor_ >= 0; }
  const std::string& path() const { return path_; }
  // A Gamepad source that polls this joystick (keeps it alive).
  Gamepad::Source as_source();

  static constexpr std::uint32_t reopen_interval_polls = 100;

 private:
  void try_open();
  void close_device();
  void apply_axis(std::uint8_t number, std::int16_t value);
  void apply_button(std::uint8_t number, bool pressed);

  std::string path_;
  int descriptor_ = -1;
  std::uint32_t polls_since_open_attempt_ = 0;
  Controller state_;
};

}  // namespace ocp::sim_app
