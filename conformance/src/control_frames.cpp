#include "conformance/control_frames.hpp"

#include <fmt/format.h>

#include "ocp/frame.hpp"

namespace ocp::conformance {

namespace {

// The controller object: every button and axis of seed 001, the pad's ones set.
std::string crafted_controller_json(const CraftedPad& pad, bool unknown_fields) {
  std::string buttons;
  for (const std::string_view name : controller_buttons) {
    const bool pressed = (name == "a" && pad.a) || (name == "back" && pad.back) || (name == "start" && pad.start) ||
                         (!pad.also_pressed.empty() && name == pad.also_pressed);
    buttons += fmt::format(R"({}"{}":{})", buttons.empty() ? "" : ",", name, pressed ? "true" : "false");
  }
  return fmt::format(R"({{"buttons":{{{0}{1}}},"axes":{{"left_x":{2:.3f},"left_y":0.0,)"
                     R"("right_x":0.0,"right_y":0.0,"left_trigger":{3:.3f},"right_trigger":{4:.3f}}}{5}}})",
                     buttons, unknown_fields ? R"(,"paddle_1":true)" : "", pad.left_x, pad.left_trigger,
                     pad.right_trigger, unknown_fields ? R"(,"haptics":{"rumble":[0.1,0.2]})" : "");
}

}  // namespace

std::string control_payload(const CraftedControl& c) {
  std::string controller;
  switch (c.controller) {
    case CraftedController::null:
      controller = "null";
      break;
    case CraftedController::absent:
      break;
    case CraftedController::driving:
      controller =
          crafted_controller_json(CraftedPad{.a = true, .left_x = 0.25, .right_trigger = 0.5}, c.unknown_fields);
      break;
    case CraftedController::safe_default:
      controller = crafted_controller_json(CraftedPad{}, c.unknown_fields);
      break;
    case CraftedController::pad:
      controller = crafted_controller_json(c.pad, c.unknown_fields);
      break;
  }
  std::string out =
      fmt::format(R"({{{0}{1}"telemetry":{{"latency":12,"fault":{2},"fault_reason":"{3}"{4}{5}}},)"
                  R"("ack_time":{6},"ack_time_mac":{7})",
                  c.unknown_fields ? R"("protocol_revision":"2099.1","x_vendor":{"nested":[1,{"k":null}]},)" : "",
                  c.controller == CraftedController::absent ? std::string() : R"("controller":)" + controller + ",",
                  c.fault ? "true" : "false", c.fault_reason,
                  c.missing_cameras.empty() ? std::string() : R"(,"missing_cameras":)" + c.missing_cameras,
                  c.unknown_fields ? R"(,"jitter_ms":1.5)" : "", c.ack.ack_time, c.ack.ack_time_mac);
  if (!c.client_user_data.empty()) out += R"(,"client_user_data":)" + c.client_user_data;
  if (c.unknown_fields) out += R"(,"future_flag":false)";
  out += "}";
  return out;
}

std::string frame_bytes(std::string_view payload) {
  std::string out;
  out.reserve(frame_header_bytes + payload.size());
  append_length_prefix(static_cast<std::uint32_t>(payload.size()), out);  // the codec's, unchecked
  out.append(payload);
  return out;
}

std::string oversized_frame(std::uint32_t declared_length) {
  // Filler that is JSON-looking, so a client that ignores the limit chokes visibly on it.
  std::string payload = R"({"filler":")";
  payload.append(declared_length - payload.size() - 2, 'x');
  payload += "\"}";
  return frame_bytes(payload);
}

std::string nested_user_data(int depth) {
  std::string open, close;
  for (int i = 0; i < depth; ++i) {
    if (i % 2 == 0) {
      open += fmt::format(R"({{"level{}":)", i);
      close = "}" + close;
    } else {
      open += "[";
      close = R"(,"tail",3.5,null,true])" + close;
    }
  }
  return open + R"({"mode":"manual","unicode":"\u00e5\u00e4\u00f6"})" + close;
}

}  // namespace ocp::conformance
