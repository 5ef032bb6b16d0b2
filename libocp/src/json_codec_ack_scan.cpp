// The pair of a control message without decoding the rest of it (json_codec.hpp,
// scan_control_ack_pair): the vehicle client's echo path. A single pass over the top-level
// object: keys are compared as raw bytes, every other value is skipped by tracking strings and
// bracket depth only. Anything it does not fully understand gives nullopt, and the caller falls
// back to decode_control_message, so the scan never has to be a JSON validator — it only has to
// agree with the decoder whenever both succeed (fuzz_control_message checks exactly that).
#include <optional>

#include "ocp/json_codec.hpp"

namespace ocp {
namespace {

class AckScanner {
 public:
  explicit AckScanner(std::string_view json) : text_(json) {}

  std::optional<AckPair> scan() {
    skip_space();
    if (!take('{')) return std::nullopt;
    skip_space();
    if (take('}')) return std::nullopt;   // no members: no pair
    for (;;) {
      std::string_view key;
      if (!read_plain_key(key)) return std::nullopt;
      skip_space();
      if (!take(':')) return std::nullopt;
      skip_space();
      // Duplicate keys: the decoder keeps the last occurrence, so the scan does too.
      if (key == "ack_time") {
        if (!read_plain_integer(ack_time_)) return std::nullopt;
      } else if (key == "ack_time_mac") {
        std::uint64_t mac = 0;
        if (!read_plain_integer(mac) || mac > 0xFFFF'FFFFULL) return std::nullopt;
        ack_time_mac_ = static_cast<std::uint32_t>(mac);
      } else if (!skip_value()) {
        return std::nullopt;
      }
      skip_space();
      if (take(',')) {
        skip_space();
        continue;
      }
      if (!take('}') || !ack_time_ || !ack_time_mac_) return std::nullopt;
      return AckPair{*ack_time_, *ack_time_mac_};
    }
  }

 private:
  bool at_end() const { return position_ >= text_.size(); }
  char peek() const { return text_[position_]; }
  bool take(char wanted) {
    if (at_end() || peek() != wanted) return false;
    ++position_;
    return true;
  }
  void skip_space() {
    while (!at_end() && (peek() == ' ' || peek() == '\t' || peek() == '\n' || peek() == '\r')) ++position_;
  }

  // A key without escapes (an escaped key could spell "ack_time" differently: leave it to the decoder).
  bool read_plain_key(std::string_view& key) {
    if (!take('"')) return false;
    const std::size_t start = position_;
    while (!at_end() && peek() != '"') {
      if (peek() == '\\') return false;
      ++position_;
    }
    if (at_end()) return false;
    key = text_.substr(start, position_ - start);
    ++position_;
    return true;
  }

  // JSON's integer form only ("0" or no leading zero), ending where a member ends: "1.0",
  // "1e3", "-1" and overflow are the decoder's to reject.
  bool read_plain_integer(std::optional<std::uint64_t>& out) {
    std::uint64_t value = 0;
    if (!read_plain_integer(value)) return false;
    out = value;
    return true;
  }
  bool read_plain_integer(std::uint64_t& out) {
    const std::size_t start = position_;
    std::uint64_t value = 0;
    while (!at_end() && peek() >= '0' && peek() <= '9') {
      const auto digit = static_cast<std::uint64_t>(peek() - '0');
      if (value > (~std::uint64_t{0} - digit) / 10) return false;
      value = value * 10 + digit;
      ++position_;
    }
    const std::size_t digits = position_ - start;
    if (digits == 0 || (digits > 1 && text_[start] == '0')) return false;
    if (!at_end() && peek() != ',' && peek() != '}' && peek() != ' ' && peek() != '\t' && peek() != '\n' &&
        peek() != '\r') {
      return false;
    }
    out = value;
    return true;
  }

  // Any other value: strings (with escapes), nested objects and arrays by depth, and scalars up
  // to the next delimiter. Well-formedness is the decoder's business.
  bool skip_value() {
    int depth = 0;
    while (!at_end()) {
      const char c = peek();
      if (c == '"') {
        if (!skip_string()) return false;
      } else if (c == '{' || c == '[') {
        ++depth;
        ++position_;
      } else if (c == '}' || c == ']') {
        if (depth == 0) return true;   // the end of the top-level object
        --depth;
        ++position_;
      } else if (c == ',' && depth == 0) {
        return true;
      } else {
        ++position_;
      }
      if (depth == 0 && (c == '"' || c == '}' || c == ']')) return true;
    }
    return false;
  }
  bool skip_string() {
    ++position_;   // the opening quote
    while (!at_end()) {
      const char c = peek();
      ++position_;
      if (c == '"') return true;
      if (c == '\\') ++position_;   // whatever is escaped cannot end the string
    }
    return false;
  }

  std::string_view text_;
  std::size_t position_ = 0;
  std::optional<std::uint64_t> ack_time_;
  std::optional<std::uint32_t> ack_time_mac_;
};

}  // namespace

std::optional<AckPair> scan_control_ack_pair(std::string_view json) { return AckScanner(json).scan(); }

}  // namespace ocp
