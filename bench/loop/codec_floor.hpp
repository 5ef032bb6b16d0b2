#pragma once
// The codec floor of a virtual fleet point: the CPU that only the wire work of one vehicle
// cycle takes, with no World, no executor, no events. Per vehicle and cycle, as the Streamer
// and the reference client do it: the Streamer issues the pair (AckMac::compute) and encodes
// the control message, the client decodes it and encodes its response carrying the pair, the
// Streamer decodes the response, and the returned pair's MAC is verified (LatencyLoop::
// check_returned). The messages are samples the point really sent (fleet_recorder.hpp), copied
// to N vehicles with N MAC keys and N buffers, so the working set is the fleet's size. Set
// against the point's CPU per simulated second it says how much of that is the codec itself.
// Left out: the client's building of its user data (encode_user_data), the Player's messages.
#include <cstddef>
#include <cstdint>
#include <string>

namespace ocp::bench {

struct CodecFloor {
  bool ok = false;
  std::string error;
  std::uint64_t vehicle_cycles = 0;
  double cpu_s = 0;                      // this thread's CPU over the measured rounds
  double us_per_vehicle_cycle = 0;
  // CPU seconds per simulated second at 100 Hz: µs per vehicle cycle × N × 100.
  double cpu_per_simulated_s = 0;
};

// `control_json` and `response_json`: one control message and one vehicle response as sent.
// One unmeasured round over the N vehicles, then rounds for about `duration_s` (at least two).
CodecFloor measure_codec_floor(int vehicles, const std::string& control_json, const std::string& response_json,
                               double duration_s);

}  // namespace ocp::bench
