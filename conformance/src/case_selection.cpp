#include <cstdint>
#include <string>
#include <string_view>

#include "conformance/runner.hpp"

namespace ocp::conformance {
namespace {

bool glob(std::string_view pattern, std::string_view text) {
  if (pattern.empty()) return text.empty();
  if (pattern.front() == '*') {
    for (std::size_t i = 0; i <= text.size(); ++i) {
      if (glob(pattern.substr(1), text.substr(i))) return true;
    }
    return false;
  }
  if (text.empty()) return false;
  if (pattern.front() != '?' && pattern.front() != text.front()) return false;
  return glob(pattern.substr(1), text.substr(1));
}

// The number at the front of `text` (its digits removed), for case_id_before.
std::uint64_t leading_number(std::string_view& text) {
  std::uint64_t value = 0;
  while (!text.empty() && text.front() >= '0' && text.front() <= '9') {
    value = value * 10 + static_cast<std::uint64_t>(text.front() - '0');
    text.remove_prefix(1);
  }
  return value;
}

}  // namespace

bool case_id_before(const std::string& a, const std::string& b) {
  std::string_view x(a), y(b);
  while (!x.empty() && !y.empty()) {
    const bool x_digit = x.front() >= '0' && x.front() <= '9', y_digit = y.front() >= '0' && y.front() <= '9';
    if (x_digit && y_digit) {
      const std::uint64_t m = leading_number(x), n = leading_number(y);
      if (m != n) return m < n;
      continue;
    }
    if (x.front() != y.front()) return x.front() < y.front();
    x.remove_prefix(1);
    y.remove_prefix(1);
  }
  return x.size() < y.size();
}

bool matches_any(const std::string& id, const std::string& patterns) {
  std::string_view rest(patterns);
  while (!rest.empty()) {
    const std::size_t comma = rest.find(',');
    const std::string_view one = rest.substr(0, comma);
    // A bare prefix ("vehicle/2") selects that section and everything under it.
    if (!one.empty() && (glob(one, id) || (one.find_first_of("*?") == std::string_view::npos &&
                                           (id == one || id.rfind(std::string(one) + "/", 0) == 0)))) {
      return true;
    }
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
  return false;
}

std::vector<VehicleCase> select_cases(std::vector<VehicleCase> cases, const std::string& include,
                                      const std::string& exclude) {
  std::vector<VehicleCase> out;
  for (VehicleCase& c : cases) {
    if (!include.empty() && !matches_any(c.body.info.id, include)) continue;
    if (!exclude.empty() && matches_any(c.body.info.id, exclude)) continue;
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace ocp::conformance
