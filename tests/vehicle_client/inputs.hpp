#pragma once
// Time and gamepad inputs the vehicle client's tests share.
#include <cstdint>

#include "ocp/executor.hpp"
#include "ocp/messages.hpp"

namespace ocp::testing {

constexpr Micros ms(std::int64_t value) { return Micros{value * 1000}; }

// The Start button alone: what arms the safety layer.
inline Controller start_pressed() {
  Controller controller;
  controller.buttons.start = true;
  return controller;
}

}  // namespace ocp::testing
