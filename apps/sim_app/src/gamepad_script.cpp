#include "sim_app/gamepad_script.hpp"

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string_view>

#include "sim_app/file_loaders.hpp"
#include "sim_app/linux_joystick.hpp"

namespace ocp::sim_app {

namespace {

constexpr Millis drive_loop_length{3'000};
constexpr Millis drive_step{100};
constexpr Millis start_press_length{200};
constexpr Millis steering_period{2'800};   // one full swing per loop, back to straight
constexpr double steering_amplitude = 0.4;
constexpr double throttle_trigger = -0.5;   // raw trigger: -1 released, +1 fully pressed
constexpr std::string_view joystick_prefix = "js:";

}  // namespace

Recording drive_recording() {
  Recording recording;
  // Start alone, with everything else neutral: the interlock enables only then.
  RecordedState press;
  press.controller.buttons.start = true;
  recording.states.push_back(press);
  for (Millis t = start_press_length; t < drive_loop_length; t += drive_step) {
    RecordedState state;
    state.time = t;
    const double phase = 2.0 * std::numbers::pi * static_cast<double>((t - start_press_length).count()) /
                         static_cast<double>(steering_period.count());
    state.controller.axes.left_x = steering_amplitude * std::sin(phase);
    state.controller.axes.right_trigger = throttle_trigger;
    recording.states.push_back(state);
  }
  // A last line with the loop length (its state is never shown: playback wraps there).
  RecordedState end = recording.states.back();
  end.time = drive_loop_length;
  recording.states.push_back(end);
  return recording;
}

Result<GamepadScript> parse_gamepad_script(const std::string& text) {
  GamepadScript script;
  script.description = text;
  if (text == "idle") {
    script.loop = false;
    return script;
  }
  if (text == "drive") {
    script.recording = drive_recording();
    return script;
  }
  if (text.starts_with(joystick_prefix)) {
    script.joystick_device = text.substr(joystick_prefix.size());
    // A typo must not look like an unplugged joystick: the device has to be there at start.
    std::error_code error;
    if (script.joystick_device.empty() || !std::filesystem::exists(script.joystick_device, error)) {
      return Error{std::make_error_code(std::errc::no_such_device),
                   "--gamepad '" + text + "': no joystick device at '" + script.joystick_device +
                       "' (plug it in, or check the path: ls /dev/input/js*)"};
    }
    return script;
  }
  auto recording = load_gamepad_recording(text);
  if (!recording) {
    return Error{recording.error().code,
                 "--gamepad '" + text + "': not idle, drive or a readable recording file: " +
                     recording.error().detail};
  }
  script.recording = std::move(*recording);
  return script;
}

void apply_gamepad_script(Gamepad& gamepad, const GamepadScript& script, SimTime start) {
  if (!script.joystick_device.empty()) {
    gamepad.set_source(std::make_shared<LinuxJoystick>(script.joystick_device)->as_source());
    return;
  }
  if (script.recording.states.empty()) {
    gamepad.set_idle();
    return;
  }
  gamepad.set_recording(script.recording, start, script.loop);
}

}  // namespace ocp::sim_app
