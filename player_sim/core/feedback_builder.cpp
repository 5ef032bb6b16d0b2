// The VehicleOcpShared entry of one vehicle (SPEC §4.1), built from what its Streamer sent.
#include <array>

#include "ocp/mutants.hpp"
#include "vehicle_link.hpp"

namespace ocp {

namespace {

// `out` = the identifiers of `ids`, rewritten only when they differ: a fleet's entries are
// refreshed every frame and their fault lists rarely change, so this keeps the strings.
template <class Ids>
void assign_identifiers(std::vector<std::string>& out, const Ids& ids) {
  std::size_t index = 0;
  bool same = true;
  for (FaultId id : ids) {
    same = same && index < out.size() && out[index] == fault_identifier(id);
    ++index;
  }
  if (same && index == out.size()) return;
  out.clear();
  for (FaultId id : ids) out.emplace_back(fault_identifier(id));
}

// The faults of a set in table order, on the stack (FaultSet::to_vector allocates).
struct FaultList {
  std::array<FaultId, fault_count> ids{};
  std::size_t size = 0;
  explicit FaultList(const FaultSet& set) {
    for (std::size_t index = 0; index < ids.size(); ++index) {
      const auto id = static_cast<FaultId>(index);
      if (set.contains(id)) ids[size++] = id;
    }
  }
  const FaultId* begin() const { return ids.data(); }
  const FaultId* end() const { return ids.data() + size; }
};

}  // namespace

void refresh_vehicle_feedback(VehicleFeedback& entry, const VehicleLink& link, SimTime now, SimTime measured_since) {
  entry.ping_latency_ms = link.ping_latency_ms;
  entry.is_monitor = link.monitor;
  bool refresh_faults = true;
#ifdef OCP_MUTANTS
  refresh_faults = !mutant_active(Mutant::feedback_fault_lists_stale);
#endif
  if (refresh_faults) assign_identifiers(entry.sender_fault, FaultList(link.sender_faults));
  entry.ack = link.latest_sei ? *link.latest_sei : AckPair{};
  const StreamerFeedback* feedback = link.last_feedback ? &*link.last_feedback : nullptr;
  Micros data_age = now - measured_since;  // never updated: age since the link started
  if (feedback != nullptr) {
    entry.message_latency_roundtrip = feedback->latency_ms;
    if (feedback->missing_cameras.empty()) {
      entry.missing_cameras.reset();
    } else {
      entry.missing_cameras = feedback->missing_cameras;
    }
    if (refresh_faults) assign_identifiers(entry.receiver_fault, feedback->receiver_faults);
    entry.vehicle_data = feedback->vehicle_data;   // copy-assignment reuses the strings' buffers
    entry.last_remote_input = feedback->last_remote_input;
    if (feedback->vehicle_data_age) {
      data_age = *feedback->vehicle_data_age + (now - link.feedback_arrived_at);
    }
  } else {
    entry.message_latency_roundtrip.reset();
    entry.missing_cameras.reset();
    entry.receiver_fault.clear();
    entry.vehicle_data.reset();
    entry.last_remote_input.reset();
  }
  entry.ms_since_last_vehicle_data =
      data_age.count() > 0 ? static_cast<std::uint64_t>(to_whole_ms(data_age)) : 0;
}

VehicleFeedback build_vehicle_feedback(const VehicleLink& link, SimTime now, SimTime measured_since) {
  VehicleFeedback entry;
  refresh_vehicle_feedback(entry, link, now, measured_since);
  return entry;
}

}  // namespace ocp
