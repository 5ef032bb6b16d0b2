#include "ocp/number_text.hpp"

#include <charconv>
#include <cmath>

#include <fmt/format.h>

namespace ocp {

namespace {

std::string quoted(std::string_view text) {
  if (text.empty()) return "an empty value";
  return fmt::format("'{}'", text);
}

// 60000 rather than 60000.000000 or 6e+04; fractions as they are (0.01).
std::string bound(double value) {
  if (value == std::floor(value) && std::abs(value) < 1e15) return fmt::format("{:.0f}", value);
  return fmt::format("{}", value);
}

}  // namespace

std::optional<double> parse_finite_number(std::string_view text) {
  if (text.empty()) return std::nullopt;
  double value = 0.0;
  const char* end = text.data() + text.size();
  // from_chars takes no leading '+' or spaces, and (in general format) no hex: what is left is
  // what a reader calls a decimal number — plus "nan"/"inf", rejected just below.
  const auto [rest, error] = std::from_chars(text.data(), end, value);
  if (error != std::errc{} || rest != end || !std::isfinite(value)) return std::nullopt;
  return value;
}

std::optional<std::uint64_t> parse_unsigned_number(std::string_view text) {
  if (text.empty() || text.front() < '0' || text.front() > '9') return std::nullopt;
  std::uint64_t value = 0;
  const char* end = text.data() + text.size();
  const auto [rest, error] = std::from_chars(text.data(), end, value);
  if (error != std::errc{} || rest != end) return std::nullopt;
  return value;
}

std::optional<std::string> check_real_text(std::string_view text, double min, double max) {
  const auto value = parse_finite_number(text);
  if (!value || *value < min || *value > max) {
    return fmt::format("expected a number in {}..{}, got {}", bound(min), bound(max), quoted(text));
  }
  return std::nullopt;
}

std::optional<std::string> check_positive_real_text(std::string_view text, double max) {
  const auto value = parse_finite_number(text);
  if (!value || !(*value > 0.0) || *value > max) {
    return fmt::format("expected a number above 0 and at most {}, got {}", bound(max), quoted(text));
  }
  return std::nullopt;
}

std::optional<std::string> check_unsigned_text(std::string_view text, std::uint64_t min,
                                               std::uint64_t max) {
  const auto value = parse_unsigned_number(text);
  if (!value || *value < min || *value > max) {
    return fmt::format("expected a whole number in {}..{}, got {}", min, max, quoted(text));
  }
  return std::nullopt;
}

}  // namespace ocp
