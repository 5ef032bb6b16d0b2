#pragma once
// Tiny helpers to write JSON text by hand (the reports are flat and small).
#include <fmt/format.h>

#include <string>
#include <string_view>

#include "sim_app/report_text.hpp"
#include "stats.hpp"

namespace ocp::bench {

inline std::string json_string(std::string_view text) { return "\"" + report::json_escape(text) + "\""; }

// Finite numbers only: JSON has no NaN or infinity.
inline std::string json_number(double value) {
  if (!(value == value) || value > 1e300 || value < -1e300) return "null";
  return fmt::format("{:.6g}", value);
}

inline std::string json_summary(const Summary& summary) {
  return fmt::format(R"({{"count":{},"p50":{},"p90":{},"p99":{},"p99_9":{},"max":{},"mean":{}}})", summary.count,
                     json_number(summary.p50), json_number(summary.p90), json_number(summary.p99),
                     json_number(summary.p999), json_number(summary.max), json_number(summary.mean));
}

}  // namespace ocp::bench
