#pragma once
// Compact JSON output for the fixed message layouts. Structure (braces, keys) is written as
// literal text by the encoders; this class formats the values. Output is always valid JSON:
// strings are escaped and invalid UTF-8 in them becomes U+FFFD; doubles use the shortest
// text that reads back to the same value; non-finite doubles (JSON has none) become null.
#include <charconv>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "ocp/messages.hpp"

namespace ocp::json_detail {

class JsonWriter {
 public:
  explicit JsonWriter(std::string& out) : out_(out) { out_.clear(); }

  void literal(std::string_view text) { out_.append(text); }
  void literal(char c) { out_.push_back(c); }
  void boolean(bool value) {
    out_.append(value ? std::string_view("true") : std::string_view("false"));
  }
  void null() { out_.append("null"); }
  void u64(std::uint64_t value) {
    char buffer[20];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    out_.append(buffer, result.ptr);
  }
  void number(double value);
  void string(std::string_view text);
  // Trusted to be one JSON value (see validate_raw_json); an empty one is written as null.
  void raw(const RawJson& value) {
    if (value.text.empty()) {
      null();
    } else {
      out_.append(value.text);
    }
  }

  // `"ack_time":N,"ack_time_mac":M`: the pair as both the control message and the vehicle
  // response carry it (SPEC §5), written in one place.
  void ack_pair_members(const AckPair& ack) {
    literal("\"ack_time\":");
    u64(ack.ack_time);
    literal(",\"ack_time_mac\":");
    u64(ack.ack_time_mac);
  }
  void controller(const Controller& controller);
  void optional_controller(const std::optional<Controller>& controller);
  void string_array(const std::vector<std::string>& values);
  void vehicle_user_data(const VehicleUserData& data);

 private:
  std::string& out_;
};

}  // namespace ocp::json_detail
