// What the Player publishes on its EventBus: sender-fault edges per vehicle, gamepad plug
// edges, active-vehicle changes, source locking (client_data.cpp) and its :4001 client's
// frames and connection (FramedConnection). Callers test events.active() first.
#include <utility>

#include "player_impl.hpp"

namespace ocp {

void PlayerCore::Impl::publish(EventBody body) {
  events.publish(Event{executor.now(), component(), std::move(body)});
}

void PlayerCore::Impl::publish_sender_fault_changes(const std::string& vehicle,
                                                    const FaultSet& before, const FaultSet& after) {
  for (std::size_t index = 0; index < fault_count; ++index) {
    const auto id = static_cast<FaultId>(index);
    const bool active = after.contains(id);
    if (before.contains(id) != active) {
      publish(FaultEvent{FaultSide::operator_station, id, active, vehicle});
    }
  }
}

void PlayerCore::Impl::publish_frame_changes(bool gamepad_plugged,
                                             const std::optional<std::string>& active) {
  if (published_gamepad_plugged != gamepad_plugged) {
    published_gamepad_plugged = gamepad_plugged;
    publish(GamepadChange{gamepad_plugged});
  }
  if (published_active_vehicle != active) {
    published_active_vehicle = active;
    ActiveVehicleChange change;
    if (active) change.vehicle = std::string_view(**published_active_vehicle);
    publish(change);
  }
}

}  // namespace ocp
