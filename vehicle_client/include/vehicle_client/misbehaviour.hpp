#pragma once
// Deliberate protocol violations for tests and conformance demos (`--misbehave …`). All off by
// default; a correct integration never sets any of them. Each one produces a specific fault
// on the Streamer side, listed next to it.
#include <cstddef>
#include <cstdint>
#include <string>

#include "ocp/time.hpp"

namespace ocp {

struct Misbehaviour {
  bool stop_echo = false;           // keep echoing the first pair ever received → HighLatency
  bool corrupt_mac = false;         // echo ack_time_mac with bits flipped → InvalidMac
  Micros delay_responses{0};        // send every response this late → latency grows / HighLatency
  bool oversized_frames = false;    // every response is a >16 KiB frame (drained) → InvalidMac
  bool ack_through_double = false;  // ack_time parsed via double: > 2^53 breaks → InvalidMac
  bool malformed_json = false;      // responses are not JSON → Streamer closes the connection
  bool silent = false;              // never send anything → Streamer's 2 s read timeout

  bool any() const;
  // "none" or a comma-separated list of the active switches, e.g. "stop-echo, corrupt-mac".
  std::string describe() const;
};

// The MAC the corrupt-mac switch sends instead of the real one (always differs from it).
inline constexpr std::uint32_t corrupt_mac_mask = 0xA5A5A5A5u;
// Payload size of an oversized response frame: one byte over the 16 KiB limit.
inline constexpr std::size_t oversized_payload_bytes = 16385;

}  // namespace ocp
