#include "vehicle_client/misbehaviour.hpp"

#include <fmt/format.h>

namespace ocp {

bool Misbehaviour::any() const {
  return stop_echo || corrupt_mac || delay_responses.count() > 0 || oversized_frames ||
         ack_through_double || malformed_json || silent;
}

std::string Misbehaviour::describe() const {
  std::string text;
  const auto add = [&text](std::string_view name) {
    if (!text.empty()) text += ", ";
    text += name;
  };
  if (stop_echo) add("stop-echo");
  if (corrupt_mac) add("corrupt-mac");
  if (delay_responses.count() > 0) add(fmt::format("delay-responses-ms {}", delay_responses.count() / 1000.0));
  if (oversized_frames) add("oversized-frames");
  if (ack_through_double) add("ack-through-double");
  if (malformed_json) add("malformed-json");
  if (silent) add("silent");
  return text.empty() ? "none" : text;
}

}  // namespace ocp
