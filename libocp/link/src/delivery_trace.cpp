#include "ocp/delivery_trace.hpp"
#include "ocp/escaped_excerpt.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <sstream>
#include <system_error>

namespace ocp {
namespace {

Error trace_error(std::string detail) {
  return Error{std::make_error_code(std::errc::invalid_argument), std::move(detail)};
}

std::string_view trimmed(std::string_view line) {
  const auto first = line.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = line.find_last_not_of(" \t\r");
  return line.substr(first, last - first + 1);
}

}  // namespace

Result<DeliveryTrace> DeliveryTrace::parse(std::string_view text, const std::string& name) {
  std::vector<std::int64_t> millis;
  std::size_t line_number = 0;
  std::size_t last_line = 0;
  while (!text.empty()) {
    const auto end = text.find('\n');
    const std::string_view raw = text.substr(0, end);
    text = end == std::string_view::npos ? std::string_view{} : text.substr(end + 1);
    ++line_number;
    const std::string_view line = trimmed(raw);
    if (line.empty()) continue;  // blank lines (a final newline, spacing) carry nothing
    const std::string where = name + ":" + std::to_string(line_number) + ": ";
    std::int64_t value = 0;
    const auto [rest, status] = std::from_chars(line.data(), line.data() + line.size(), value);
    if (status == std::errc::result_out_of_range || (status == std::errc{} && rest == line.data() + line.size() &&
                                                     value > max_timestamp_ms)) {
      return trace_error(where + "timestamp '" + escaped_excerpt(line) + "' is beyond " +
                         std::to_string(max_timestamp_ms) + " ms");
    }
    if (status != std::errc{} || rest != line.data() + line.size() || value < 0) {
      return trace_error(where + "expected a whole number of milliseconds, got '" + escaped_excerpt(line) + "'");
    }
    if (!millis.empty() && value < millis.back()) {
      return trace_error(where + "timestamp " + std::to_string(value) + " goes backwards (previous line says " +
                         std::to_string(millis.back()) + ")");
    }
    if (millis.size() == max_lines) {
      return trace_error(where + "more than " + std::to_string(max_lines) + " delivery opportunities");
    }
    millis.push_back(value);
    last_line = line_number;
  }
  if (millis.empty()) return trace_error(name + ": empty trace (no delivery opportunities)");
  if (millis.back() == 0) {
    // The period is the last timestamp: a trace that ends at 0 ms would loop in no time.
    return trace_error(name + ":" + std::to_string(last_line) +
                       ": the last timestamp must be > 0 ms (it is the period the trace loops with)");
  }
  return DeliveryTrace{std::move(millis), name};
}

Micros DeliveryTrace::time_of(std::uint64_t index) const {
  const std::uint64_t count = millis_.size();
  const auto cycle = static_cast<std::int64_t>(index / count);
  return Micros{(cycle * millis_.back() + millis_[index % count]) * 1000};
}

std::uint64_t DeliveryTrace::first_at_or_after(Micros elapsed) const {
  const std::int64_t period_micros = period().count();
  const std::int64_t at = std::max<std::int64_t>(0, elapsed.count());
  std::int64_t cycle = at / period_micros;
  std::int64_t offset = at - cycle * period_micros;
  // At an exact multiple of the period the previous cycle's last opportunities (stamped with
  // the period itself) come first.
  if (offset == 0 && cycle > 0) {
    --cycle;
    offset = period_micros;
  }
  const auto it = std::lower_bound(millis_.begin(), millis_.end(), offset,
                                   [](std::int64_t ms, std::int64_t micros) { return ms * 1000 < micros; });
  return static_cast<std::uint64_t>(cycle) * millis_.size() + static_cast<std::uint64_t>(it - millis_.begin());
}

}  // namespace ocp
