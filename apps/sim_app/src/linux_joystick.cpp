// Non-blocking reader for Linux joystick devices (see linux_joystick.hpp).
#include "sim_app/linux_joystick.hpp"

#include <fcntl.h>
#include <linux/joystick.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

namespace ocp::sim_app {

LinuxJoystick::LinuxJoystick(std::string path) : path_(std::move(path)) { try_open(); }

LinuxJoystick::~LinuxJoystick() { close_device(); }

void LinuxJoystick::try_open() {
  polls_since_open_attempt_ = 0;
  descriptor_ = ::open(path_.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  // The driver replays the current state as JS_EVENT_INIT events right after open.
  state_ = Controller::safe_default();
}

void LinuxJoystick::close_device() {
  if (descriptor_ >= 0) ::close(descriptor_);
  descriptor_ = -1;
}

std::optional<Controller> LinuxJoystick::poll() {
  if (descriptor_ < 0) {
    if (++polls_since_open_attempt_ < reopen_interval_polls) return std::nullopt;
    try_open();
    if (descriptor_ < 0) return std::nullopt;
  }
  js_event events[64];
  while (true) {
    const ssize_t bytes = ::read(descriptor_, events, sizeof(events));
    if (bytes < 0) {
      if (errno == EINTR) continue;
      if (errno == EAGAIN || errno == EWOULDBLOCK) break;
      close_device();  // ENODEV after an unplug
      return std::nullopt;
    }
    if (bytes == 0) {
      close_device();
      return std::nullopt;
    }
    const std::size_t count = static_cast<std::size_t>(bytes) / sizeof(js_event);
    for (std::size_t index = 0; index < count; ++index) {
      const js_event& event = events[index];
      const std::uint8_t type = event.type & static_cast<std::uint8_t>(~JS_EVENT_INIT);
      if (type == JS_EVENT_AXIS) apply_axis(event.number, event.value);
      if (type == JS_EVENT_BUTTON) apply_button(event.number, event.value != 0);
    }
  }
  return state_;
}

Gamepad::Source LinuxJoystick::as_source() {
  return [self = shared_from_this()](SimTime) { return self->poll(); };
}

void LinuxJoystick::apply_axis(std::uint8_t number, std::int16_t value) {
  const double scaled = std::clamp(static_cast<double>(value) / 32767.0, -1.0, 1.0);
  Axes& axes = state_.axes;
  Buttons& buttons = state_.buttons;
  switch (number) {
    case 0: axes.left_x = scaled; break;
    case 1: axes.left_y = scaled; break;
    case 2: axes.left_trigger = scaled; break;
    case 3: axes.right_x = scaled; break;
    case 4: axes.right_y = scaled; break;
    case 5: axes.right_trigger = scaled; break;
    case 6:
      buttons.dpad_left = value < 0;
      buttons.dpad_right = value > 0;
      break;
    case 7:
      buttons.dpad_up = value < 0;
      buttons.dpad_down = value > 0;
      break;
    default: break;
  }
}

void LinuxJoystick::apply_button(std::uint8_t number, bool pressed) {
  Buttons& buttons = state_.buttons;
  switch (number) {
    case 0: buttons.a = pressed; break;
    case 1: buttons.b = pressed; break;
    case 2: buttons.x = pressed; break;
    case 3: buttons.y = pressed; break;
    case 4: buttons.left_bumper = pressed; break;
    case 5: buttons.right_bumper = pressed; break;
    case 6: buttons.back = pressed; break;
    case 7: buttons.start = pressed; break;
    case 8: buttons.guide = pressed; break;
    case 9: buttons.left_thumb = pressed; break;
    case 10: buttons.right_thumb = pressed; break;
    default: break;
  }
}

}  // namespace ocp::sim_app
