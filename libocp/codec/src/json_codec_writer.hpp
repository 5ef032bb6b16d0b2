#pragma once
// Compact JSON output for the fixed message layouts. Structure (braces, keys) is written as
// literal text by the encoders; this class formats the values. Output is always valid JSON:
// strings are escaped and invalid UTF-8 in them becomes U+FFFD; doubles use the shortest
// text that reads back to the same value; non-finite doubles (JSON has none) become null.
#include <charconv>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "ocp/messages.hpp"

namespace ocp::json_detail {

class JsonWriter {
 public:
  // Writes into `out` directly, through a cursor: `out` is grown to its capacity here, and cut
  // to what was written when the writer goes (so `out` is complete only after that). A call to
  // string::append for each literal was a third of encoding a control message.
  explicit JsonWriter(std::string& out) : out_(out) {
    out_.resize(out_.capacity());
    at_ = out_.data();
    end_ = at_ + out_.size();
  }
  ~JsonWriter() { out_.resize(static_cast<std::size_t>(at_ - out_.data())); }
  JsonWriter(const JsonWriter&) = delete;
  JsonWriter& operator=(const JsonWriter&) = delete;

  void literal(std::string_view text) {
    if (text.empty()) return;   // memcpy from a null view is undefined, even of 0 bytes
    room(text.size());
    std::memcpy(at_, text.data(), text.size());
    at_ += text.size();
  }
  void literal(char c) {
    room(1);
    *at_++ = c;
  }
  void boolean(bool value) { value ? literal("true") : literal("false"); }
  void null() { literal("null"); }
  void u64(std::uint64_t value) {
    room(20);
    at_ = std::to_chars(at_, at_ + 20, value).ptr;
  }
  void number(double value);
  void string(std::string_view text);
  // Trusted to be one JSON value (see validate_raw_json); an empty one is written as null.
  void raw(const RawJson& value) {
    if (value.text.empty()) {
      null();
    } else {
      literal(value.text);
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
  // At least `bytes` writable bytes at the cursor.
  void room(std::size_t bytes) {
    if (static_cast<std::size_t>(end_ - at_) < bytes) grow(bytes);
  }
  void grow(std::size_t bytes);
  // The shortest text of a decimal with 1 to 15 fraction digits, when `value` is one.
  bool short_decimal(double value);

  std::string& out_;
  char* at_ = nullptr;
  char* end_ = nullptr;
};

}  // namespace ocp::json_detail
