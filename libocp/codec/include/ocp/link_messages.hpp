#pragma once
// What crosses the Oden com channel between a Player and a Streamer (SPEC §1, §5, §6).
// These are in-process values, not JSON: the real com channel is proprietary, and the
// simulator only needs its timing, loss and content.
#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "ocp/faults.hpp"
#include "ocp/messages.hpp"
#include "ocp/time.hpp"

namespace ocp {

// Player → Streamer, once per Player frame (≤ 100 Hz), only on control (non-monitor) links.
struct OperatorControl {
  std::uint64_t sequence = 0;
  std::optional<Controller> controller;        // nullopt when ocp_disable_gamepad is set
  std::optional<RawJson> client_user_data;     // the `user_data` of this vehicle's entry
  std::optional<AckPair> returned_ack;         // echoed SEI pair; nullopt when none to echo
  std::vector<FaultId> sender_faults;          // operator-side faults, table order
};

// Streamer → Player, once per Streamer frame.
struct StreamerFeedback {
  std::uint64_t sequence = 0;
  std::vector<FaultId> receiver_faults;        // vehicle-side faults, table order
  std::optional<std::uint64_t> latency_ms;     // measured loop latency; nullopt until measured
  std::vector<std::string> missing_cameras;
  std::optional<VehicleUserData> vehicle_data; // latest from the vehicle client, repeated
  std::optional<Micros> vehicle_data_age;      // now − arrival of that data, at send time
  std::optional<Controller> last_remote_input; // controller last sent to the vehicle
};

// Streamer → Player, per camera at its fps. `sei` carries the latest echoed pair.
struct VideoFrame {
  std::string camera;
  std::uint64_t frame_number = 0;
  std::optional<AckPair> sei;
  std::uint32_t size_bytes = 0;               // encoded size, for bandwidth simulation
};

// Com-channel ping, Player → Streamer every 100 ms, answered by a Pong carrying the same id.
struct Ping {
  std::uint64_t id = 0;
  SimTime sent_at{};
};
struct Pong {
  std::uint64_t id = 0;
  SimTime ping_sent_at{};
};

using LinkMessage = std::variant<OperatorControl, StreamerFeedback, VideoFrame, Ping, Pong>;

// Approximate size on the wire, used by bandwidth caps and byte counters.
std::size_t wire_size_bytes(const LinkMessage& message);

}  // namespace ocp
