#pragma once
// Strict checks of numbers typed on a command line. CLI11's own conversions let NaN and
// infinities through every range check (every comparison with NaN is false), turn "-1" into
// 2^64-1 for unsigned options and accept an empty value; these accept only what a reader
// would take for a number in range:
//   real:     a finite decimal number ("20", "0.5", "1e3"), nothing before or after it
//   unsigned: decimal digits only, no sign, at most the given maximum
// Each returns nullopt when the text is fine, or the problem in words ("expected a number in
// 0..60000, got 'nan'"), ready to follow the option name.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace ocp {

// The whole text as a finite double, or nullopt.
std::optional<double> parse_finite_number(std::string_view text);
// The whole text as a u64 (digits only), or nullopt (also on overflow).
std::optional<std::uint64_t> parse_unsigned_number(std::string_view text);

// A finite number in [min, max].
std::optional<std::string> check_real_text(std::string_view text, double min, double max);
// A finite number in (min, max]: for periods, rates and sizes that must be positive.
std::optional<std::string> check_positive_real_text(std::string_view text, double max);
// Digits only, in [min, max].
std::optional<std::string> check_unsigned_text(std::string_view text, std::uint64_t min,
                                               std::uint64_t max);

}  // namespace ocp
