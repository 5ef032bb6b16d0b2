#include "codec_floor.hpp"

#include <chrono>
#include <vector>

#include "ocp/json_codec.hpp"
#include "ocp/mac.hpp"
#include "process_usage.hpp"

namespace ocp::bench {

namespace {

// What one vehicle holds: its Streamer's key and outgoing message, its client's response, and
// the two reused text buffers (as StreamerCore's json_buffer and ResponseWriter's).
struct Vehicle {
  AckMac mac;
  OcpControlMessage control;
  VehicleResponseMessage response;
  std::string control_json, response_json;
};

}  // namespace

CodecFloor measure_codec_floor(int vehicles, const std::string& control_json, const std::string& response_json,
                               double duration_s) {
  CodecFloor floor;
  auto control = decode_control_message(control_json);
  auto response = decode_vehicle_response(response_json);
  if (vehicles <= 0 || !control || !response) {
    floor.error = vehicles <= 0 ? "no vehicles" : "the sample messages do not decode";
    return floor;
  }
  std::vector<Vehicle> fleet;
  fleet.reserve(static_cast<std::size_t>(vehicles));
  for (int index = 0; index < vehicles; ++index) {
    MacKey key{};
    for (std::size_t byte = 0; byte < key.size(); ++byte) key[byte] = static_cast<std::uint8_t>(index * 31 + byte);
    fleet.push_back(Vehicle{AckMac(key), *control, *response, {}, {}});
  }
  std::uint64_t ack_time = control->ack.ack_time;
  bool all_valid = true;
  auto round = [&] {
    ack_time += 10'000;   // the next tick, 10 ms later
    for (Vehicle& vehicle : fleet) {
      vehicle.control.ack = AckPair{ack_time, vehicle.mac.compute(ack_time)};   // Streamer: issue
      encode_control_message(vehicle.control, vehicle.control_json);
      auto received = decode_control_message(vehicle.control_json);             // client
      if (!received) {
        all_valid = false;
        continue;
      }
      vehicle.response.ack = received->ack;
      encode_vehicle_response(vehicle.response, vehicle.response_json);
      auto returned = decode_vehicle_response(vehicle.response_json);            // Streamer
      if (!returned || !vehicle.mac.verify(returned->ack.ack_time, returned->ack.ack_time_mac)) all_valid = false;
    }
  };
  round();
  const double cpu_start = thread_cpu_seconds();
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(duration_s);
  std::uint64_t rounds = 0;
  while (rounds < 2 || std::chrono::steady_clock::now() < end) {
    round();
    ++rounds;
  }
  floor.cpu_s = thread_cpu_seconds() - cpu_start;
  if (!all_valid) {
    floor.error = "a message or pair did not survive its round trip";
    return floor;
  }
  floor.vehicle_cycles = rounds * static_cast<std::uint64_t>(vehicles);
  floor.us_per_vehicle_cycle = floor.cpu_s * 1e6 / static_cast<double>(floor.vehicle_cycles);
  floor.cpu_per_simulated_s = floor.us_per_vehicle_cycle * 1e-6 * vehicles * 100.0;
  floor.ok = true;
  return floor;
}

}  // namespace ocp::bench
