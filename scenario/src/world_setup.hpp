#pragma once
// Model → World pieces: the WorldConfig for a seed, and the gamepad script on a Gamepad.
#include <cstdint>

#include "scenario/model.hpp"

namespace ocp::scenario {

WorldConfig world_config(const Scenario& scenario, std::uint64_t seed);
void apply_gamepad(Gamepad& gamepad, const GamepadScriptSetting& setting, SimTime start);

}  // namespace ocp::scenario
