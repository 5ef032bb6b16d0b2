#pragma once
// CLI11 validators over ocp/number_text.hpp, for every numeric option of every executable:
//   app.add_option("--link-delay-ms", value)->check(ocp::cli::real(0.0, 60'000.0));
// They run on the text before CLI11 converts it, so NaN, infinities, a sign on an unsigned
// option and empty values never reach the conversion. CLI11 reports the failure as
// "--link-delay-ms: expected a number in 0..60000, got 'nan'".
#include <CLI/CLI.hpp>
#include <cstdint>
#include <limits>
#include <string>

#include "ocp/number_text.hpp"
#include <fmt/format.h>

namespace ocp::cli {

inline CLI::Validator real(double min, double max) {
  return CLI::Validator(
      [min, max](std::string& text) { return check_real_text(text, min, max).value_or(""); },
      fmt::format("in {:g}..{:g}", min, max));
}

inline CLI::Validator positive_real(double max) {
  return CLI::Validator(
      [max](std::string& text) { return check_positive_real_text(text, max).value_or(""); },
      fmt::format("in (0, {:g}]", max));
}

inline CLI::Validator whole(std::uint64_t min = 0,
                            std::uint64_t max = std::numeric_limits<std::uint64_t>::max()) {
  return CLI::Validator(
      [min, max](std::string& text) { return check_unsigned_text(text, min, max).value_or(""); },
      fmt::format("in {}..{}", min, max));
}

}  // namespace ocp::cli
