// The VehicleOcpShared entry of one vehicle (SPEC §4.1), built from what its Streamer sent.
#include "vehicle_link.hpp"

namespace ocp {

VehicleFeedback build_vehicle_feedback(const VehicleLink& link, SimTime now, SimTime measured_since) {
  VehicleFeedback entry;
  entry.ping_latency_ms = link.ping_latency_ms;
  entry.is_monitor = link.monitor;
  entry.sender_fault = link.sender_faults.identifiers();
  if (link.latest_sei) entry.ack = *link.latest_sei;
  const StreamerFeedback* feedback = link.last_feedback ? &*link.last_feedback : nullptr;
  Micros data_age = now - measured_since;  // never updated: age since the link started
  if (feedback != nullptr) {
    entry.message_latency_roundtrip = feedback->latency_ms;
    if (!feedback->missing_cameras.empty()) entry.missing_cameras = feedback->missing_cameras;
    for (FaultId id : feedback->receiver_faults) {
      entry.receiver_fault.emplace_back(fault_identifier(id));
    }
    entry.vehicle_data = feedback->vehicle_data;
    entry.last_remote_input = feedback->last_remote_input;
    if (feedback->vehicle_data_age) {
      data_age = *feedback->vehicle_data_age + (now - link.feedback_arrived_at);
    }
  }
  entry.ms_since_last_vehicle_data =
      data_age.count() > 0 ? static_cast<std::uint64_t>(to_whole_ms(data_age)) : 0;
  return entry;
}

}  // namespace ocp
