// Model → World pieces (world_setup.hpp).
#include "world_setup.hpp"

#include "sim_app/gamepad_script.hpp"

namespace ocp::scenario {

WorldConfig world_config(const Scenario& scenario, std::uint64_t seed) {
  WorldConfig config = scenario.world;
  config.seed = seed;
  config.deterministic_keys = true;   // VirtualWorld forces it too; say so for the reader
  return config;
}

void apply_gamepad(Gamepad& gamepad, const GamepadScriptSetting& setting, SimTime start) {
  switch (setting.kind) {
    case GamepadScriptSetting::Kind::idle: gamepad.set_idle(); return;
    case GamepadScriptSetting::Kind::drive:
      // sim_app's built-in script: start press, then throttle and steering, looped.
      gamepad.set_recording(sim_app::drive_recording(), start, true);
      return;
    case GamepadScriptSetting::Kind::constant: gamepad.set_constant(setting.constant); return;
    case GamepadScriptSetting::Kind::waveform: gamepad.set_waveform(setting.waveform, start); return;
  }
}

}  // namespace ocp::scenario
