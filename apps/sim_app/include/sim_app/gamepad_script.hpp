#pragma once
// The simulated operator's gamepad (--gamepad): a built-in script or a recording file in the
// text format of player/gamepad.hpp.
//   idle   — connected and neutral (the safe default controller).
//   drive  — a 3 s loop: 200 ms of start alone (the reference vehicle's drive interlock
//            enables on a start press with neutral sticks, and a vehicle that connects late
//            gets the next press), then a light throttle while steering left and right.
//   <path> — a recording file, looped.
//   js:<device> — a real Linux joystick, e.g. js:/dev/input/js0 (linux_joystick.hpp); an
//            unplugged joystick is an absent gamepad (SPEC §4.1: the null controller is sent)
//            and is reopened when it comes back.
#include <string>

#include "ocp/error.hpp"
#include "player/gamepad.hpp"

namespace ocp::sim_app {

struct GamepadScript {
  std::string description = "drive";
  Recording recording;     // empty for idle
  bool loop = true;
  std::string joystick_device;   // js:<device>; then `recording` is unused
};

[[nodiscard]] Result<GamepadScript> parse_gamepad_script(const std::string& text);
// The built-in "drive" recording (steps every 100 ms).
Recording drive_recording();
// Installs the script on `gamepad`, with playback starting at `start` (a joystick is polled
// at every sample instead).
void apply_gamepad_script(Gamepad& gamepad, const GamepadScript& script, SimTime start);

}  // namespace ocp::sim_app
