#include "json_codec_reader.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

namespace ocp::json_detail {
namespace {

constexpr std::size_t max_echoed_chars = 32;  // peer text quoted in an error detail

std::string quote_number(std::string_view text) {
  if (text.size() <= max_echoed_chars) return std::string(text);
  return std::string(text.substr(0, max_echoed_chars)) + "...";
}


// What a number token's text holds, read as an unsigned integer. The tokenizer checked the JSON
// number grammar: digits alone mean no sign, fraction or exponent.
enum class Digits { value, too_large, not_digits };

// One pass: 19 digits cannot overflow (10^19 - 1 < 2^64), so only the digits after them check
// each step (the first loop has one test a digit).
Digits read_digits(std::string_view text, std::uint64_t& out) {
  constexpr std::size_t safe_digits = 19;
  std::uint64_t value = 0;
  std::size_t i = 0;
  for (const std::size_t safe_end = std::min(text.size(), safe_digits); i < safe_end; ++i) {
    const auto digit = static_cast<std::uint64_t>(static_cast<unsigned char>(text[i]) - '0');
    if (digit > 9) return Digits::not_digits;
    value = value * 10 + digit;
  }
  for (; i < text.size(); ++i) {
    const auto digit = static_cast<std::uint64_t>(static_cast<unsigned char>(text[i]) - '0');
    if (digit > 9) return Digits::not_digits;
    if (value > (std::numeric_limits<std::uint64_t>::max() - digit) / 10) {
      // Still report a non-digit further on as not_digits, as the two-pass check did.
      for (std::size_t j = i + 1; j < text.size(); ++j) {
        if (static_cast<unsigned char>(text[j]) - '0' > 9) return Digits::not_digits;
      }
      return Digits::too_large;
    }
    value = value * 10 + digit;
  }
  out = value;
  return Digits::value;
}

// Exact fast path for the decimals our encoders write ("-0.25", "57.7081"): no exponent, at
// most 19 digits (so the integer cannot overflow), the digits as an integer at most 2^53 and at
// most 22 of them after the point. Both the integer and the power of ten are then exact
// doubles, so one correctly rounded division gives the correctly rounded value (Clinger's fast
// path). Anything else goes to from_chars.
bool parse_short_decimal(std::string_view text, double& out) {
  static constexpr double powers_of_ten[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                             1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                             1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
  constexpr std::ptrdiff_t max_digits = 19;   // 10^19 - 1 < 2^64
  constexpr std::uint64_t max_exact = 1ULL << 53;
  constexpr std::ptrdiff_t max_fraction_digits = 22;  // 10^22 is the largest exact power of ten
  const char* at = text.data();
  const char* const end = at + text.size();
  const bool negative = at != end && *at == '-';
  if (negative) ++at;
  // The integer part, then the fraction's digits, in two plain loops (one test a byte). More
  // than 19 digits may wrap `digits` around: such texts are refused below, by their length.
  std::uint64_t digits = 0;
  const char* const integer_begin = at;
  for (; at != end && static_cast<unsigned char>(*at - '0') <= 9; ++at) {
    digits = digits * 10 + static_cast<unsigned char>(*at - '0');
  }
  const std::ptrdiff_t integer_digits = at - integer_begin;
  std::ptrdiff_t fraction_digits = 0;
  if (at != end && *at == '.') {
    const char* const fraction_begin = ++at;
    for (; at != end && static_cast<unsigned char>(*at - '0') <= 9; ++at) {
      digits = digits * 10 + static_cast<unsigned char>(*at - '0');
    }
    fraction_digits = at - fraction_begin;
  }
  if (at != end) return false;  // exponent
  if (integer_digits + fraction_digits > max_digits || digits > max_exact ||
      fraction_digits > max_fraction_digits) {
    return false;
  }
  const double value = static_cast<double>(digits) / powers_of_ten[fraction_digits];
  out = negative ? -value : value;
  return true;
}

// from_chars reports both overflow and underflow as out of range; JSON's grammar and
// RapidJSON's exponent limit leave underflow only for negative exponents or a zero integral
// part, where the closest double is a signed zero.
bool parse_double(std::string_view text, double& out) {
  if (parse_short_decimal(text, out)) return true;
  const char* first = text.data();
  const char* last = text.data() + text.size();
  const auto [end, error] = std::from_chars(first, last, out);
  if (error == std::errc() && end == last) return std::isfinite(out);
  if (error != std::errc::result_out_of_range) return false;
  const bool negative = text.front() == '-';
  const std::string_view magnitude = negative ? text.substr(1) : text;
  const bool underflow = magnitude.find("e-") != std::string_view::npos ||
                         magnitude.find("E-") != std::string_view::npos ||
                         magnitude.front() == '0';
  if (!underflow) return false;
  out = negative ? -0.0 : 0.0;
  return true;
}

}  // namespace

bool Decoder::fail(PeerError code, std::string_view message) {
  code_ = code;
  message_.assign(message);
  path_reversed_.clear();
  return false;
}

bool Decoder::fail_missing(std::string_view field) {
  fail(PeerError::missing_field, "required field missing");
  return in_field(field, false);
}

bool Decoder::in_field(std::string_view field, bool ok) {
  if (!ok) path_reversed_.emplace_back(field);
  return ok;
}

bool Decoder::in_element(std::size_t position, bool ok) {
  if (!ok) {
    // Built piecewise: GCC 12 warns falsely (-Wrestrict) on "[" + std::string + "]".
    std::string segment(1, '[');
    segment += std::to_string(position);
    segment += ']';
    path_reversed_.push_back(std::move(segment));
  }
  return ok;
}

Error Decoder::take_error() const {
  std::string detail;
  for (auto segment = path_reversed_.rbegin(); segment != path_reversed_.rend(); ++segment) {
    if (!detail.empty() && segment->front() != '[') detail += '.';
    detail += *segment;
  }
  if (detail.empty()) detail = "(top level)";
  detail += ": ";
  detail += message_;
  return Error{make_error_code(code_), std::move(detail)};
}

bool Decoder::expect_object(std::size_t index) {
  if (kind(index) == TokenKind::object_begin) return true;
  return fail(PeerError::wrong_type, "expected object");
}

bool Decoder::read_u64(std::size_t index, std::uint64_t& out) {
  constexpr std::string_view expected = "expected unsigned 64-bit integer";
  if (kind(index) != TokenKind::number) return fail(PeerError::wrong_type, expected);
  const std::string_view text = tape_.text_of(tape_.tokens[index]);
  if (read_digits(text, out) == Digits::value) return true;
  return fail(PeerError::out_of_range,
              std::string(expected) + ", got " + quote_number(text));
}

bool Decoder::read_u32(std::size_t index, std::uint32_t& out) {
  constexpr std::string_view expected = "expected unsigned 32-bit integer";
  if (kind(index) != TokenKind::number) return fail(PeerError::wrong_type, expected);
  const std::string_view text = tape_.text_of(tape_.tokens[index]);
  std::uint64_t wide = 0;
  if (read_digits(text, wide) == Digits::value && wide <= std::numeric_limits<std::uint32_t>::max()) {
    out = static_cast<std::uint32_t>(wide);
    return true;
  }
  return fail(PeerError::out_of_range,
              std::string(expected) + ", got " + quote_number(text));
}

bool Decoder::read_integral(std::size_t index, std::uint64_t& out) {
  constexpr std::string_view expected = "expected non-negative integer";
  if (kind(index) != TokenKind::number) return fail(PeerError::wrong_type, expected);
  const std::string_view text = tape_.text_of(tape_.tokens[index]);
  const Digits digits = read_digits(text, out);
  if (digits == Digits::value) return true;
  if (digits == Digits::not_digits) {
    // 2^64 as a double; every whole double below it converts exactly.
    constexpr double u64_limit = 18446744073709551616.0;
    double value = 0.0;
    if (parse_double(text, value) && value >= 0.0 && value < u64_limit &&
        std::floor(value) == value) {
      out = static_cast<std::uint64_t>(value);
      return true;
    }
  }
  return fail(PeerError::out_of_range,
              std::string(expected) + ", got " + quote_number(text));
}

bool Decoder::read_double(std::size_t index, double& out) {
  if (kind(index) != TokenKind::number) return fail(PeerError::wrong_type, "expected number");
  const std::string_view text = tape_.text_of(tape_.tokens[index]);
  if (parse_double(text, out)) return true;
  return fail(PeerError::out_of_range, "expected finite number, got " + quote_number(text));
}

bool Decoder::read_string(std::size_t index, std::string& out) {
  if (kind(index) != TokenKind::string) return fail(PeerError::wrong_type, "expected string");
  out.assign(tape_.text_of(tape_.tokens[index]));
  return true;
}

bool Decoder::read_string_array(std::size_t index, std::vector<std::string>& out) {
  if (kind(index) != TokenKind::array_begin) {
    return fail(PeerError::wrong_type, "expected array of strings");
  }
  out.clear();
  const std::size_t end = tape_.tokens[index].end_index;
  for (std::size_t position = index + 1; position < end; position = tape_.next(position)) {
    const std::size_t element = out.size();
    if (!in_element(element, read_string(position, out.emplace_back()))) return false;
  }
  return true;
}

bool Decoder::read_raw(std::size_t index, RawJson& out) {
  out.text.assign(tape_.source_of(index));
  return true;
}

}  // namespace ocp::json_detail
