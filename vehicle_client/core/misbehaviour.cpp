#include "vehicle_client/misbehaviour.hpp"

#include <fmt/format.h>

namespace ocp {

namespace {
constexpr BadResponse all_bad_responses[] = {BadResponse::none, BadResponse::missing_field, BadResponse::wrong_type,
                                             BadResponse::not_an_object, BadResponse::ack_time_out_of_range,
                                             BadResponse::eof_mid_frame};
}  // namespace

std::string_view bad_response_name(BadResponse kind) {
  switch (kind) {
    case BadResponse::none: return "none";
    case BadResponse::missing_field: return "missing-field";
    case BadResponse::wrong_type: return "wrong-type";
    case BadResponse::not_an_object: return "not-an-object";
    case BadResponse::ack_time_out_of_range: return "ack-time-out-of-range";
    case BadResponse::eof_mid_frame: return "eof-mid-frame";
  }
  return "none";
}

std::optional<BadResponse> parse_bad_response(std::string_view name) {
  std::string dashed(name);
  for (char& c : dashed) c = c == '_' ? '-' : c;   // scenario files write keys with _
  for (BadResponse kind : all_bad_responses) {
    if (bad_response_name(kind) == dashed) return kind;
  }
  return std::nullopt;
}

bool Misbehaviour::any() const {
  return stop_echo || corrupt_mac || delay_responses.count() > 0 || oversized_frames ||
         ack_through_double || malformed_json || silent || bad_response != BadResponse::none;
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
  if (bad_response != BadResponse::none) add(fmt::format("bad-response {}", bad_response_name(bad_response)));
  return text.empty() ? "none" : text;
}

}  // namespace ocp
