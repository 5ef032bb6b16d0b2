#include "json_codec_writer.hpp"

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

void JsonWriter::number(double value) {
  // Whole values of small magnitude (most axes sit at 0, -1 or 1) skip the shortest
  // round-trip search: below 10^4 it prints their integer digits anyway (fixed notation wins
  // ties with exponent notation). NaN fails both compares and takes the general path.
  if (value > -10000.0 && value < 10000.0) {
    const auto whole = static_cast<int>(value);
    if (static_cast<double>(whole) == value) {
      if (whole == 0 && std::signbit(value)) {
        out_.append("-0.0");
        return;
      }
      char digits[8];
      const auto result = std::to_chars(digits, digits + sizeof digits, whole);
      out_.append(digits, result.ptr);
      out_.append(".0");
      return;
    }
  }
  if (!std::isfinite(value)) {
    null();
    return;
  }
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  const std::string_view text(buffer, static_cast<std::size_t>(result.ptr - buffer));
  out_.append(text);
  // Keep whole numbers visibly floating point ("-1.0", not "-1") as the product docs show.
  if (text.find_first_of(".e") == std::string_view::npos) out_.append(".0");
}

void JsonWriter::string(std::string_view text) {
  static constexpr char hex[] = "0123456789abcdef";
  out_.push_back('"');
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
    out_.append(text.substr(clean_begin, i - clean_begin));
    switch (c) {
      case '"': out_.append("\\\""); break;
      case '\\': out_.append("\\\\"); break;
      case '\n': out_.append("\\n"); break;
      case '\r': out_.append("\\r"); break;
      case '\t': out_.append("\\t"); break;
      case '\b': out_.append("\\b"); break;
      case '\f': out_.append("\\f"); break;
      default:
        if (c < 0x20) {
          const char escaped[] = {'\\', 'u', '0', '0', hex[c >> 4], hex[c & 0xF]};
          out_.append(escaped, sizeof escaped);
        } else {
          out_.append("\\ufffd");  // a byte that does not start valid UTF-8
        }
    }
    ++i;
    clean_begin = i;
  }
  out_.append(text.substr(clean_begin));
  out_.push_back('"');
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
