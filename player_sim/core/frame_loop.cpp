// The Player frame: one OperatorControl per control vehicle, then the VehicleOcpShared object
// for every client (SPEC §4.1, §6 operator faults, §7). Also the com-channel pings.
#include <utility>

#include "ocp/invariant.hpp"
#include "player_impl.hpp"

namespace ocp {

SimTime PlayerCore::Impl::measured_since(const VehicleLink& link) const {
  // A vehicle linked after start is measured from when it was linked.
  return link.linked_at > started_at ? link.linked_at : started_at;
}

std::optional<std::string> PlayerCore::Impl::resolve_active_vehicle() const {
  if (selected_vehicle) {
    const auto found = vehicles.find(*selected_vehicle);
    if (found == vehicles.end() || found->second.monitor) return std::nullopt;
    return selected_vehicle;
  }
  // One control vehicle: active_vehicle may be omitted. Several and none selected: none.
  std::optional<std::string> only;
  for (const auto& [name, link] : vehicles) {
    if (link.monitor) continue;
    if (only) return std::nullopt;
    only = name;
  }
  return only;
}

void PlayerCore::Impl::on_frame() {
  const SimTime now = executor.now();
  ++stats.frames;
  const std::optional<Controller> sample = gamepad.sample(now);
  const std::optional<std::string> active = resolve_active_vehicle();
  if (events.active()) publish_frame_changes(sample.has_value(), active);

  for (auto& [name, link] : vehicles) {
    const bool is_active = active && *active == name;
    SenderFaultInputs inputs;
    inputs.now = now;
    inputs.measured_since = measured_since(link);
    inputs.no_feedback_timeout = config.no_feedback_timeout;
    inputs.gamepad_plugged = sample.has_value();
    inputs.is_active = is_active;
    const FaultSet before = link.sender_faults;
    link.sender_faults = evaluate_sender_faults(link, inputs);
    if (events.active()) publish_sender_fault_changes(name, before, link.sender_faults);

    if (!link.monitor) {
      OperatorControl control;
      control.sequence = link.next_control_sequence++;
      if (!link.client.disable_gamepad) {
        // Only the active vehicle gets the gamepad; everything else (and an unplugged
        // gamepad) gets the safe default controller.
        control.controller = is_active && sample ? *sample : Controller::safe_default();
      }
      if (!source_lock.stopped()) control.client_user_data = link.client.user_data;
      control.returned_ack = echo_pair(link);
      control.sender_faults = link.sender_faults.to_vector();
      if (is_active) last_input = control.controller;
      OCP_INVARIANT(!control.controller || is_active || *control.controller == Controller::safe_default(),
                    "only the active vehicle gets the gamepad; the others get the safe default");
      OCP_INVARIANT(control.sequence + 1 == link.next_control_sequence, "control sequence numbers are dense, in order");
      link.to_streamer->send(LinkMessage{std::move(control)});
      ++stats.control_messages_sent;
    }
  }
  refresh_shared(now);
  ++stats.shared_published;

  if (client && client->is_open()) send_to_client(last_shared);
  for (const SharedListener& listener : shared_listeners) listener(last_shared);
  summarise_repeated_warnings(now);
  OCP_INVARIANT(stats.shared_published == stats.frames, "one VehicleOcpShared is published per frame");
}

// Rebuilding VehicleOcpShared from scratch every frame (a fresh map, every name, fault list
// and user-data string allocated and freed again) was the Player's largest cost with a large
// fleet; the entries are refreshed in place instead. Runs after the control loop, so whoever
// reads last_shared() while that loop publishes events sees the whole previous frame.
void PlayerCore::Impl::refresh_shared(SimTime now) {
  auto& entries = last_shared.vehicle_feedback;
  auto entry = entries.begin();
  for (const auto& [name, link] : vehicles) {
    // Both maps are in name order and, while running, vehicles are only ever added (one
    // unlinked while stopped takes its entry with it): walk them together and insert the
    // entry of a vehicle linked since the last frame where it belongs.
    if (entry == entries.end() || entry->first != name) entry = entries.emplace_hint(entry, name, VehicleFeedback{});
    refresh_vehicle_feedback(entry->second, link, now, measured_since(link));
    ++entry;
  }
  last_shared.last_input = last_input;
  OCP_INVARIANT(last_shared.vehicle_feedback.size() == vehicles.size(),
                "VehicleOcpShared has exactly one entry per linked vehicle");
}

void PlayerCore::Impl::on_ping() {
  const SimTime now = executor.now();
  for (auto& [name, link] : vehicles) {
    if (link.to_streamer == nullptr) continue;
    link.to_streamer->send(LinkMessage{Ping{link.next_ping_id++, now}});
    ++stats.pings_sent;
  }
}

}  // namespace ocp
