// The pair of a control message without decoding the rest of it (json_codec.hpp,
// scan_control_ack_pair): the vehicle client's echo path. A single pass over the top-level
// object: keys are compared as raw bytes, every other value is skipped by tracking strings and
// bracket depth only. Anything it does not fully understand gives nullopt, and the caller falls
// back to decode_control_message, so the scan never has to be a JSON validator — it only has to
// agree with the decoder whenever both succeed (fuzz_control_message checks exactly that).
#include <array>
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
  // to the next delimiter. Well-formedness is the decoder's business. Only the bytes in
  // `structural` are looked at; the rest is passed over one table lookup each (this runs on
  // every control message, ahead of the full decode: it must cost much less than that decode).
  bool skip_value() {
    const char* const begin = text_.data();
    const char* const end = begin + text_.size();
    const char* cursor = begin + position_;
    int depth = 0;
    for (;;) {
      while (cursor < end && structural[static_cast<unsigned char>(*cursor)] == 0) ++cursor;
      if (cursor >= end) return false;
      switch (structural[static_cast<unsigned char>(*cursor)]) {
        case quote:
          cursor = after_string(cursor + 1, end);
          if (cursor == nullptr) return false;
          if (depth == 0) break;
          continue;
        case open:
          ++depth;
          ++cursor;
          continue;
        case close:
          if (depth == 0) break;   // the end of the top-level object: the scalar before it ends here
          ++cursor;
          if (--depth == 0) break;
          continue;
        default:   // comma
          if (depth == 0) break;
          ++cursor;
          continue;
      }
      position_ = static_cast<std::size_t>(cursor - begin);
      return true;
    }
  }
  // Just past the quote that closes the string whose contents start at `cursor`, or nullptr.
  static const char* after_string(const char* cursor, const char* end) {
    for (;;) {
      while (cursor < end && !string_stop[static_cast<unsigned char>(*cursor)]) ++cursor;
      if (cursor >= end) return nullptr;
      if (*cursor == '"') return cursor + 1;
      if (end - cursor < 2) return nullptr;
      cursor += 2;   // a backslash: whatever it escapes cannot end the string
    }
  }
  static constexpr std::array<bool, 256> string_stop = [] {
    std::array<bool, 256> table{};
    table['"'] = true;
    table['\\'] = true;
    return table;
  }();

  enum : std::uint8_t { other, quote, open, close, comma };
  static constexpr std::array<std::uint8_t, 256> structural = [] {
    std::array<std::uint8_t, 256> table{};
    table['"'] = quote;
    table['{'] = open;
    table['['] = open;
    table['}'] = close;
    table[']'] = close;
    table[','] = comma;
    return table;
  }();

  std::string_view text_;
  std::size_t position_ = 0;
  std::optional<std::uint64_t> ack_time_;
  std::optional<std::uint32_t> ack_time_mac_;
};

}  // namespace

std::optional<AckPair> scan_control_ack_pair(std::string_view json) { return AckScanner(json).scan(); }

}  // namespace ocp
