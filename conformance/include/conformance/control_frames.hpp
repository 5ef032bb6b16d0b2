#pragma once
// Hand-made OcpControlMessage frames for the cases that feed a client shapes the simulated
// operator would not produce on demand (controller null, default controller with fault, deep
// client_user_data, unknown fields, extreme pairs, oversized or hand-cut frames).
#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "ocp/messages.hpp"

namespace ocp::conformance {

// absent: no "controller" key at all (seed 001's schema makes it optional). pad: the buttons
// and axes of CraftedControl::pad (the safety cases drive, enable and stop with them).
enum class CraftedController { driving, null, safe_default, absent, pad };

// The gamepad fields the safety cases set (the rest stay at the default safe value: buttons
// false, sticks 0). Raw values as the product sends them: triggers -1 (released) to 1.
// The 15 buttons of a controller, in the order of seed 001.
inline constexpr std::array<std::string_view, 15> controller_buttons{
    "a",     "b",          "x",           "y",       "left_bumper", "right_bumper", "back",     "start",
    "guide", "left_thumb", "right_thumb", "dpad_up", "dpad_right",  "dpad_down",    "dpad_left"};

// How the vehicle's drive interlock is worked from the gamepad: the reference client enables
// with start (sticks at rest) and stops with back; a client with its own convention names its
// buttons (ocp_conformance vehicle --enable-button/--stop-button), and the §10 cases use them.
struct InterlockButtons {
  std::string enable = "start";
  std::string stop = "back";
};

struct CraftedPad {
  bool a = false;
  bool start = false;             // the reference client's enable button
  bool back = false;              // its emergency stop
  std::string also_pressed = "";  // one more button by name (an interlock's own), "" for none
  double left_x = 0.0;
  double left_trigger = -1.0;
  double right_trigger = -1.0;
};

struct CraftedControl {
  CraftedControl() = default;
  explicit CraftedControl(AckPair pair) : ack(pair) {}
  AckPair ack;
  CraftedController controller = CraftedController::driving;
  CraftedPad pad;  // with CraftedController::pad
  bool fault = false;
  std::string fault_reason;
  std::string client_user_data;        // raw JSON value; empty → field omitted
  std::string missing_cameras = "[]";  // raw JSON value of telemetry.missing_cameras; empty → omitted
  bool unknown_fields = false;         // extra fields at top level, in telemetry and in controller
};

// The JSON text (u64 / u32 written as integers, never through a double).
std::string control_payload(const CraftedControl& control);
// uint32 LE length prefix + payload, with no size check (oversized frames are the point).
std::string frame_bytes(std::string_view payload);
// A frame whose prefix claims `declared_length` bytes of filler (an oversized frame).
std::string oversized_frame(std::uint32_t declared_length);
// Nested JSON objects and arrays `depth` levels deep.
std::string nested_user_data(int depth);

}  // namespace ocp::conformance
