#pragma once
// The four JSON messages of the two TCP APIs (SPEC §3.2, §3.3, §4.1, §4.2) as plain structs.
// Encoding and decoding live in json_codec.hpp; nothing here knows about JSON.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace ocp {

struct Buttons {
  bool a = false;
  bool b = false;
  bool x = false;
  bool y = false;
  bool left_bumper = false;
  bool right_bumper = false;
  bool back = false;
  bool start = false;
  bool guide = false;
  bool left_thumb = false;
  bool right_thumb = false;
  bool dpad_up = false;
  bool dpad_right = false;
  bool dpad_down = false;
  bool dpad_left = false;
  bool operator==(const Buttons&) const = default;
};

// Raw gamepad axes in [-1, 1]. Defaults are the safe values: sticks centred, triggers released.
struct Axes {
  double left_x = 0.0;
  double left_y = 0.0;
  double right_x = 0.0;
  double right_y = 0.0;
  double left_trigger = -1.0;
  double right_trigger = -1.0;
  bool operator==(const Axes&) const = default;
};

struct Controller {
  Buttons buttons;
  Axes axes;
  // The default (safe) controller: all buttons false, sticks 0.0, triggers -1.0.
  static Controller safe_default() { return {}; }
  bool is_safe_default() const { return *this == Controller{}; }
  bool operator==(const Controller&) const = default;
};

// The latency-loop pair. Opaque: copied byte-exact, never through a double.
struct AckPair {
  std::uint64_t ack_time = 0;
  std::uint32_t ack_time_mac = 0;
  bool operator==(const AckPair&) const = default;
};

// A JSON value carried unchanged (user data). `text` is one complete JSON value.
struct RawJson {
  std::string text;
  bool operator==(const RawJson&) const = default;
};

struct Telemetry {
  std::uint64_t latency_ms = 0;                // "latency"
  bool fault = false;
  std::string fault_reason;                    // display strings joined with ", "
  std::vector<std::string> missing_cameras;    // always encoded; absent on decode → empty
  bool operator==(const Telemetry&) const = default;
};

// Streamer → vehicle, every 10 ms.
struct OcpControlMessage {
  std::optional<Controller> controller;        // null when gamepad disabled / no gamepad path
  Telemetry telemetry;
  AckPair ack;
  std::optional<RawJson> client_user_data;     // omitted when the operator sent none
  bool operator==(const OcpControlMessage&) const = default;
};

struct Position {
  double lat = 0.0;
  double lon = 0.0;
  bool operator==(const Position&) const = default;
};

struct VehicleUserData {
  std::optional<Position> pos;                 // omitted or null → nullopt
  RawJson user_data;                           // required when vehicle_user_data is present
  bool operator==(const VehicleUserData&) const = default;
};

// Vehicle → Streamer, continuously.
struct VehicleResponseMessage {
  AckPair ack;
  std::optional<VehicleUserData> vehicle_user_data;
  bool operator==(const VehicleResponseMessage&) const = default;
};

// One vehicle's entry in VehicleOcpShared.
struct VehicleFeedback {
  std::uint64_t ping_latency_ms = 0;
  std::optional<std::uint64_t> message_latency_roundtrip;   // null until measured
  std::uint64_t ms_since_last_vehicle_data = 0;
  std::optional<std::vector<std::string>> missing_cameras;  // null when all cameras are fine
  std::vector<std::string> sender_fault;                    // fault identifiers, e.g. "InputLost"
  std::vector<std::string> receiver_fault;                  // fault identifiers, e.g. "HighLatency"
  std::optional<VehicleUserData> vehicle_data;
  std::optional<Controller> last_remote_input;
  AckPair ack;                                              // latest pair extracted from SEI
  bool is_monitor = false;
  bool operator==(const VehicleFeedback&) const = default;
};

// Player → operator client, once per Player frame (TCP :4001, web view, plugin).
struct VehicleOcpShared {
  std::map<std::string, VehicleFeedback> vehicle_feedback;
  std::optional<Controller> last_input;
  bool operator==(const VehicleOcpShared&) const = default;
};

// One vehicle's entry in ClientOcpShared. Every field is optional.
struct ClientVehicleEntry {
  std::optional<RawJson> user_data;
  std::optional<bool> ocp_disable_gamepad;
  std::optional<std::uint64_t> ack_time_returned;
  std::optional<std::uint32_t> ack_time_mac_returned;
  bool operator==(const ClientVehicleEntry&) const = default;
};

// Operator client → Player.
struct ClientOcpShared {
  std::optional<std::string> active_vehicle;
  std::map<std::string, ClientVehicleEntry> client_user_data;
  bool operator==(const ClientOcpShared&) const = default;
};

}  // namespace ocp
