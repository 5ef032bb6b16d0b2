// Series extraction and aggregates (metrics.hpp).
#include "scenario/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ocp::scenario {
namespace {

const Series* series_of(const VehicleObservations& vehicle, std::string_view metric) {
  if (metric == "latency_ms") return &vehicle.latency_ms;
  if (metric == "echo_delay_ms") return &vehicle.echo_delay_ms;
  if (metric == "control_gap_ms") return &vehicle.control_gap_ms;
  if (metric == "feedback_gap_ms") return &vehicle.feedback_gap_ms;
  return nullptr;
}

}  // namespace

bool is_counter_metric(std::string_view metric) {
  return metric == "lost_to_streamer" || metric == "lost_to_player";
}

ValueHistogram series_values(const Observations& observations, std::string_view metric,
                             const std::optional<std::string>& vehicle) {
  ValueHistogram values;
  for (const auto& [name, data] : observations.vehicles) {
    if (vehicle && name != *vehicle) continue;
    if (const auto* series = series_of(data, metric)) values.merge(series->values());
  }
  return values;
}

std::optional<double> counter_value(const Observations& observations, std::string_view metric,
                                    const std::optional<std::string>& vehicle, std::string_view aggregate) {
  std::uint64_t sent = 0, dropped = 0;
  for (const auto& [name, data] : observations.vehicles) {
    if (vehicle && name != *vehicle) continue;
    const RouteCounters& route = metric == "lost_to_streamer" ? data.to_streamer : data.to_player;
    sent += route.sent;
    dropped += route.dropped;
  }
  if (aggregate == "rate") {
    if (sent == 0) return std::nullopt;
    return static_cast<double>(dropped) / static_cast<double>(sent);
  }
  return static_cast<double>(dropped);
}

std::string format_number(double value) {
  char buffer[64];
  if (std::fabs(value - std::round(value)) < 1e-9 && std::fabs(value) < 1e15) {
    std::snprintf(buffer, sizeof buffer, "%.0f", value);
  } else {
    std::snprintf(buffer, sizeof buffer, "%.3g", value);
    if (std::fabs(value) >= 100) std::snprintf(buffer, sizeof buffer, "%.1f", value);
  }
  return buffer;
}

std::string format_seconds(SimTime time) {
  return format_number(static_cast<double>(time.count()) / 1e6) + "s";
}

}  // namespace ocp::scenario
