#include "json_codec_writer.hpp"

#include <algorithm>
#include <cmath>

namespace ocp::json_detail {
namespace {

// Length of the valid UTF-8 sequence starting at text[0], or 0 if it is not valid
// (overlong forms, surrogates and code points above U+10FFFF are invalid).
std::size_t utf8_sequence_length(std::string_view text) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  const auto continuation = [&](std::size_t i) {
    return i < text.size() && (byte(i) & 0xC0) == 0x80;
  };
  const unsigned char lead = byte(0);
  if (lead >= 0xC2 && lead <= 0xDF) return continuation(1) ? 2 : 0;
  if (lead >= 0xE0 && lead <= 0xEF) {
    if (!continuation(1) || !continuation(2)) return 0;
    if (lead == 0xE0 && byte(1) < 0xA0) return 0;  // overlong
    if (lead == 0xED && byte(1) >= 0xA0) return 0;  // surrogate
    return 3;
  }
  if (lead >= 0xF0 && lead <= 0xF4) {
    if (!continuation(1) || !continuation(2) || !continuation(3)) return 0;
    if (lead == 0xF0 && byte(1) < 0x90) return 0;  // overlong
    if (lead == 0xF4 && byte(1) >= 0x90) return 0;  // above U+10FFFF
    return 4;
  }
  return 0;
}

}  // namespace

void JsonWriter::grow(std::size_t bytes) {
  const auto used = static_cast<std::size_t>(at_ - out_.data());
  out_.resize(std::max<std::size_t>({used + bytes, 2 * out_.size(), 256}));
  at_ = out_.data() + used;
  end_ = out_.data() + out_.size();
}

void JsonWriter::number(double value) {
  // Whole values of small magnitude (most axes sit at 0, -1 or 1) skip the shortest
  // round-trip search: below 10^4 it prints their integer digits anyway (fixed notation wins
  // ties with exponent notation). NaN fails both compares and takes the general path.
  if (value > -10000.0 && value < 10000.0) {
    const auto whole = static_cast<int>(value);
    if (static_cast<double>(whole) == value) {
      if (whole == 0 && std::signbit(value)) {
        literal("-0.0");
        return;
      }
      room(8);
      at_ = std::to_chars(at_, at_ + 8, whole).ptr;
      literal(".0");
      return;
    }
  }
  if (short_decimal(value)) return;
  if (!std::isfinite(value)) {
    null();
    return;
  }
  room(32);
  char* const begin = at_;
  at_ = std::to_chars(at_, at_ + 32, value).ptr;
  // Keep whole numbers visibly floating point ("-1.0", not "-1") as the product docs show.
  const std::string_view text(begin, static_cast<std::size_t>(at_ - begin));
  if (text.find_first_of(".e") == std::string_view::npos) literal(".0");
}

// Positions, speeds and stick angles are short decimals ("57.7089"); the shortest round-trip
// search of to_chars was a sixth of a vehicle response. When |value| is at least 0.1 and the
// correctly rounded quotient digits / 10^k equals it for an integer digits < 10^15 and some k
// in 1..15, the smallest such k gives exactly to_chars's text: a decimal string with fewer
// fraction digits would read back to another double (the quotient is what reading it gives,
// digits and 10^k being exact doubles), and at these magnitudes fixed notation is shorter than
// exponent notation. tests/libocp/json_codec_number_test.cpp compares the two.
bool JsonWriter::short_decimal(double value) {
  static constexpr double powers_of_ten[] = {1e0, 1e1, 1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                             1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15};
  constexpr double digits_limit = 1e15;  // below 2^50: scaled values are exact to 1/8
  const double magnitude = std::fabs(value);
  if (!(magnitude >= 0.1 && magnitude < digits_limit)) return false;  // NaN too
  for (int k = 1; k <= 15; ++k) {
    const double scaled = magnitude * powers_of_ten[k];
    if (scaled >= digits_limit) return false;
    const auto digits = static_cast<std::int64_t>(scaled + 0.5);
    // At the right k, scaled is within two of its units in the last place (2^-51 of it) of
    // the digits; elsewhere it is almost never that close. The division, whose latency is
    // the cost here, then only checks the likely k.
    const double distance = std::fabs(scaled - static_cast<double>(digits));
    if (distance > scaled * 1e-12) continue;
    if (static_cast<double>(digits) / powers_of_ten[k] != magnitude) continue;
    room(40);
    if (value < 0) *at_++ = '-';
    if (magnitude < 1.0) {  // "0." and exactly k digits (magnitude >= 0.1)
      *at_++ = '0';
      *at_++ = '.';
      at_ = std::to_chars(at_, at_ + 16, digits).ptr;
      return true;
    }
    // The digits (at most 15, and more than k), then the last k of them moved one place right
    // to make room for the point: one 16-byte copy, within the 40 bytes of room (a byte loop
    // became a call to memmove).
    char* const end = std::to_chars(at_, at_ + 16, digits).ptr;
    char fraction[16];
    std::memcpy(fraction, end - k, sizeof fraction);
    std::memcpy(end - k + 1, fraction, sizeof fraction);
    end[-k] = '.';
    at_ = end + 1;
    return true;
  }
  return false;
}

void JsonWriter::string(std::string_view text) {
  static constexpr char hex[] = "0123456789abcdef";
  literal('"');
  std::size_t clean_begin = 0;
  std::size_t i = 0;
  while (i < text.size()) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c != '"' && c != '\\' && c < 0x80) {
      ++i;
      continue;
    }
    if (c >= 0x80) {
      const std::size_t length = utf8_sequence_length(text.substr(i));
      if (length != 0) {
        i += length;
        continue;
      }
    }
    literal(text.substr(clean_begin, i - clean_begin));
    switch (c) {
      case '"': literal("\\\""); break;
      case '\\': literal("\\\\"); break;
      case '\n': literal("\\n"); break;
      case '\r': literal("\\r"); break;
      case '\t': literal("\\t"); break;
      case '\b': literal("\\b"); break;
      case '\f': literal("\\f"); break;
      default:
        if (c < 0x20) {
          const char escaped[] = {'\\', 'u', '0', '0', hex[c >> 4], hex[c & 0xF]};
          literal(std::string_view(escaped, sizeof escaped));
        } else {
          literal("\\ufffd");  // a byte that does not start valid UTF-8
        }
    }
    ++i;
    clean_begin = i;
  }
  literal(text.substr(clean_begin));
  literal('"');
}

void JsonWriter::controller(const Controller& controller) {
  const Buttons& b = controller.buttons;
  const Axes& a = controller.axes;
  literal("{\"buttons\":{\"a\":");
  boolean(b.a);
  literal(",\"b\":");
  boolean(b.b);
  literal(",\"x\":");
  boolean(b.x);
  literal(",\"y\":");
  boolean(b.y);
  literal(",\"left_bumper\":");
  boolean(b.left_bumper);
  literal(",\"right_bumper\":");
  boolean(b.right_bumper);
  literal(",\"back\":");
  boolean(b.back);
  literal(",\"start\":");
  boolean(b.start);
  literal(",\"guide\":");
  boolean(b.guide);
  literal(",\"left_thumb\":");
  boolean(b.left_thumb);
  literal(",\"right_thumb\":");
  boolean(b.right_thumb);
  literal(",\"dpad_up\":");
  boolean(b.dpad_up);
  literal(",\"dpad_right\":");
  boolean(b.dpad_right);
  literal(",\"dpad_down\":");
  boolean(b.dpad_down);
  literal(",\"dpad_left\":");
  boolean(b.dpad_left);
  literal("},\"axes\":{\"left_x\":");
  number(a.left_x);
  literal(",\"left_y\":");
  number(a.left_y);
  literal(",\"right_x\":");
  number(a.right_x);
  literal(",\"right_y\":");
  number(a.right_y);
  literal(",\"left_trigger\":");
  number(a.left_trigger);
  literal(",\"right_trigger\":");
  number(a.right_trigger);
  literal("}}");
}

void JsonWriter::optional_controller(const std::optional<Controller>& controller) {
  if (controller) {
    this->controller(*controller);
  } else {
    null();
  }
}

void JsonWriter::string_array(const std::vector<std::string>& values) {
  literal('[');
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i != 0) literal(',');
    string(values[i]);
  }
  literal(']');
}

void JsonWriter::vehicle_user_data(const VehicleUserData& data) {
  literal("{\"pos\":");
  if (data.pos) {
    literal("{\"lat\":");
    number(data.pos->lat);
    literal(",\"lon\":");
    number(data.pos->lon);
    literal('}');
  } else {
    null();
  }
  literal(",\"user_data\":");
  raw(data.user_data);
  literal('}');
}

}  // namespace ocp::json_detail
