#include "vehicle_client/user_data.hpp"

#include <fmt/format.h>

namespace ocp {

void encode_user_data(const UserDataSample& sample, std::string& out) {
  // Formatted into a stack buffer, then copied once: this runs at the model rate (100 Hz).
  fmt::memory_buffer buffer;
  const VehicleState& vehicle = sample.vehicle;
  const SafetyOutput& safety = sample.safety;
  fmt::format_to(std::back_inserter(buffer),
                 R"({{"speed_mps":{:.3f},"heading_deg":{:.2f},"drive_state":"{}","safe_state":{},"safety_reasons":[)",
                 vehicle.speed_mps, vehicle.heading_deg(), drive_state_name(safety.drive_state),
                 safety.safe_state);
  bool first = true;
  for (std::size_t index = 0; index < safety_reason_count; ++index) {
    const auto reason = static_cast<SafetyReason>(index);
    if (!safety.reasons.contains(reason)) continue;
    // Reason names are fixed identifiers without characters that need escaping.
    fmt::format_to(std::back_inserter(buffer), R"({}"{}")", first ? "" : ",", safety_reason_name(reason));
    first = false;
  }
  fmt::format_to(std::back_inserter(buffer),
                 R"(],"throttle":{:.3f},"brake":{:.3f},"steer":{:.3f},"odometer_m":{:.2f},)"
                 R"("last_latency_ms":{},"sequence":{},"timestamp_ms":{})",
                 safety.command.throttle, safety.command.brake, safety.command.steer,
                 vehicle.odometer_m, sample.last_latency_ms, sample.sequence,
                 to_whole_ms(sample.timestamp));
  if (sample.misbehave != nullptr && sample.misbehave->any()) {
    // describe() yields switch names and digits only: safe inside a JSON string.
    fmt::format_to(std::back_inserter(buffer), R"(,"misbehave":"{}")", sample.misbehave->describe());
  }
  buffer.push_back('}');
  out.assign(buffer.data(), buffer.size());
}

}  // namespace ocp
