#pragma once
// The one JSON codec (RapidJSON). Decoders validate types and required fields and report the
// first problem with its JSON path ("telemetry.fault: expected boolean"); unknown fields are
// ignored; u64/u32 fields never pass through a double; user data is kept as raw JSON text.
// Decoders never throw and never abort, whatever the input.
//
// Encoders write compact JSON into `out` (cleared first) so callers can reuse one buffer.
//
// Decisions (tested in tests/libocp/json_codec_*_test.cpp):
// * Integers (ack_time, ack_time_mac, the *_returned pair, feedback counters) must be written
//   as JSON integers: "123.0", "1e5", "-0" and "-1" are out_of_range, like 2^64 or 2^32 for
//   a u32. telemetry.latency alone accepts any whole non-negative number ("42.0" → 42).
// * Duplicate keys: every occurrence is validated, the last one wins.
// * null counts as absent for optional fields. User data keeps its exact source bytes and may
//   be any JSON value. Strings must be valid UTF-8; NaN/Infinity literals, numbers beyond
//   the double range (RapidJSON refuses them) and embedded NUL bytes are malformed_json.
// * Encoders replace invalid UTF-8 in strings by U+FFFD, write non-finite doubles as null
//   (decoders then reject them) and an empty RawJson as null.
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "ocp/error.hpp"
#include "ocp/messages.hpp"

namespace ocp {

// Nesting limit for any decoded document (user data included); deeper → PeerError::too_deep.
inline constexpr int max_json_depth = 64;

Result<OcpControlMessage> decode_control_message(std::string_view json);
Result<VehicleResponseMessage> decode_vehicle_response(std::string_view json);
Result<VehicleOcpShared> decode_vehicle_ocp_shared(std::string_view json);
Result<ClientOcpShared> decode_client_ocp_shared(std::string_view json);

// decode_control_message in two steps, for a client that answers the pair before it looks at
// the rest of the message: start() tokenizes (on a tape of this object's own, so anything the
// caller decodes in between is safe) and gives the pair when the top-level ack_time and
// ack_time_mac read as the full decode reads them (last occurrence wins); finish() decodes the
// rest of the same tokens and returns exactly what decode_control_message(json) returns. The
// pair may come from a message that finish() then rejects. `json` must outlive finish().
class ControlMessageDecoder {
 public:
  ControlMessageDecoder();
  ~ControlMessageDecoder();
  ControlMessageDecoder(const ControlMessageDecoder&) = delete;
  ControlMessageDecoder& operator=(const ControlMessageDecoder&) = delete;

  std::optional<AckPair> start(std::string_view json);
  Result<OcpControlMessage> finish();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

void encode_control_message(const OcpControlMessage& message, std::string& out);
void encode_vehicle_response(const VehicleResponseMessage& message, std::string& out);
void encode_vehicle_ocp_shared(const VehicleOcpShared& message, std::string& out);
void encode_client_ocp_shared(const ClientOcpShared& message, std::string& out);

// Controller on its own (used by feedback's last_input / last_remote_input and by tools).
void encode_controller(const Controller& controller, std::string& out);

// Checks that `text` is exactly one well-formed JSON value (for user data built by hand).
Status validate_raw_json(std::string_view text);

}  // namespace ocp
