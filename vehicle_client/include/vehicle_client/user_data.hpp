#pragma once
// The user_data object this client reports in vehicle_user_data. Dashboards receive the latest
// vehicle data repeatedly (seed 000), so every sample carries a `sequence` that increases only
// when the model produced new data and the sim-time `timestamp_ms` of that sample.
//
//   {"speed_mps":3.214,"heading_deg":87.50,"drive_state":"enabled","safe_state":false,
//    "safety_reasons":[],"throttle":0.300,"brake":0.000,"steer":-0.100,"odometer_m":12.40,
//    "last_latency_ms":42,"sequence":1234,"timestamp_ms":12340}
// plus "misbehave":"stop-echo, …" when a misbehaviour switch is on. Bounded size: every field
// is bounded (six short reason names at most), so even the worst case stays under 1 KiB.
//
// One encode per model sample, not per response: the client encodes this text when the model
// advances (every model_step) and every response until the next sample carries the identical
// text. That is what `sequence`/`timestamp_ms` promise — they name the model sample, so equal
// sequence ⇒ equal text, and a new sequence always comes with a later timestamp.
// Numbers are fixed-point at the resolution that matters, not shortest round-trip: speed and
// commands to 0.001 (mm/s), heading and odometer to 0.01 (° / cm). Negative values that round
// to zero print as 0; a non-finite value prints as null so the text stays valid JSON. (The
// position is not in here: it is vehicle_user_data.pos, encoded by the libocp codec.)
#include <cstdint>
#include <string>

#include "ocp/time.hpp"
#include "vehicle_client/misbehaviour.hpp"
#include "vehicle_client/safety_layer.hpp"
#include "vehicle_client/vehicle_model.hpp"

namespace ocp {

struct UserDataSample {
  const VehicleState& vehicle;
  const SafetyOutput& safety;
  std::uint64_t last_latency_ms = 0;
  std::uint64_t sequence = 0;
  SimTime timestamp{0};
  const Misbehaviour* misbehave = nullptr;  // reported only when a switch is on
};

// Writes the JSON object into `out` (cleared first; its capacity is reused, so the steady
// state allocates nothing).
void encode_user_data(const UserDataSample& sample, std::string& out);

}  // namespace ocp
