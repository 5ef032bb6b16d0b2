#pragma once
// Measured series and their k6-style aggregates (avg, min, max, med, p(N), count, rate).
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "scenario/observer.hpp"

namespace ocp::scenario {

// The values of a metric: one vehicle's, or all vehicles' together (vehicle = nullopt).
// Counters (lost_to_streamer, lost_to_player) give no series: see counter_value.
ValueHistogram series_values(const Observations& observations, std::string_view metric,
                             const std::optional<std::string>& vehicle);
bool is_counter_metric(std::string_view metric);
// lost_*: count = messages dropped on that route, rate = dropped / sent.
std::optional<double> counter_value(const Observations& observations, std::string_view metric,
                                    const std::optional<std::string>& vehicle, std::string_view aggregate);

// nullopt when the series is empty (count gives 0); percentiles by linear interpolation
// between closest ranks (ValueHistogram::aggregate).
inline std::optional<double> aggregate(const ValueHistogram& values, std::string_view aggregate, double percentile) {
  return values.aggregate(aggregate, percentile);
}

// "12.5", "3" — short, stable formatting for reports and verdicts.
std::string format_number(double value);
std::string format_seconds(SimTime time);   // "12.5s"

}  // namespace ocp::scenario
