#pragma once
// The two messages codec_bench measures, shared by its files (codec_bench.cpp: ours and
// nlohmann; codec_bench_simdjson.cpp: the decode speed limit).

namespace ocp::bench {

// Seed 000, verbatim (tests/data/seeds/000_control_message.json).
inline constexpr const char* control_text = R"({
  "controller": {
    "buttons": {
      "a": false,
      "b": false,
      "x": false,
      "y": false,
      "left_bumper": false,
      "right_bumper": false,
      "back": false,
      "start": false,
      "guide": false,
      "left_thumb": false,
      "right_thumb": false,
      "dpad_up": false,
      "dpad_right": false,
      "dpad_down": false,
      "dpad_left": false
    },
    "axes": {
      "left_x": 0.0,
      "left_y": 0.0,
      "right_x": 0.0,
      "right_y": 0.0,
      "left_trigger": -1.0,
      "right_trigger": -1.0
    }
  },
  "telemetry": {
    "latency": 42,
    "fault": false,
    "fault_reason": ""
  },
  "ack_time": 123456,
  "ack_time_mac": 987654321,
  "client_user_data": {
    "mode": "manual"
  }
}
)";

// Seed 000, "Response with vehicle data" (tests/data/seeds/000_response_with_vehicle_data.json).
inline constexpr const char* response_text = R"({
  "ack_time": 123456,
  "ack_time_mac": 987654321,
  "vehicle_user_data": {
    "pos": {
      "lat": 57.7089,
      "lon": 11.9746
    },
    "user_data": {
      "speed_mps": 1.4,
      "drive_state": "enabled"
    }
  }
}
)";

}  // namespace ocp::bench
