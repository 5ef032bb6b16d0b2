#pragma once
// Deliberate protocol violations for tests and conformance demos (`--misbehave …`). All off by
// default; a correct integration never sets any of them. Each one produces a specific fault
// on the Streamer side, listed next to it.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "ocp/time.hpp"

namespace ocp {

// A response that breaks SPEC §2 / §3.3 in one way. The Streamer closes the connection on each
// (SPEC §2: "a required field missing or of the wrong type, a JSON value that is not an
// object, a short read → close that connection, log the reason"); the client reconnects.
enum class BadResponse {
  none,
  missing_field,          // no ack_time_mac
  wrong_type,             // ack_time as a string
  not_an_object,          // a JSON array: [ack_time, ack_time_mac]
  ack_time_out_of_range,  // ack_time 2^64, one past the u64 range
  eof_mid_frame,          // half a frame, then the client hangs up
};
std::string_view bad_response_name(BadResponse kind);   // "missing-field", … ("none")
std::optional<BadResponse> parse_bad_response(std::string_view name);   // accepts _ for -

struct Misbehaviour {
  bool stop_echo = false;           // keep echoing the first pair ever received → HighLatency
  bool corrupt_mac = false;         // echo ack_time_mac with bits flipped → InvalidMac
  Micros delay_responses{0};        // send every response this late → latency grows / HighLatency
  bool oversized_frames = false;    // every response is a >16 KiB frame (drained) → InvalidMac
  bool ack_through_double = false;  // ack_time parsed via double: > 2^53 breaks → InvalidMac
  bool malformed_json = false;      // responses are not JSON → Streamer closes the connection
  bool silent = false;              // never send anything → Streamer's 2 s read timeout
  BadResponse bad_response = BadResponse::none;   // every response broken so → Streamer closes

  bool any() const;
  // "none" or a comma-separated list of the active switches, e.g. "stop-echo, corrupt-mac".
  std::string describe() const;
};

// The MAC the corrupt-mac switch sends instead of the real one (always differs from it).
inline constexpr std::uint32_t corrupt_mac_mask = 0xA5A5A5A5u;
// Payload size of an oversized response frame: one byte over the 16 KiB limit.
inline constexpr std::size_t oversized_payload_bytes = 16385;

}  // namespace ocp
