#include "sim_app/pair_rejection_notes.hpp"

#include <variant>

namespace ocp::sim_app {

void PairRejectionNotes::follow(EventBus& streamer_events) {
  subscriptions_.push_back(streamer_events.subscribe([this](const Event& event) { on_event(event); }));
}

const std::string* PairRejectionNotes::hint(std::string_view vehicle) const {
  const auto found = hints_.find(vehicle);
  return found == hints_.end() ? nullptr : &found->second;
}

void PairRejectionNotes::on_event(const Event& event) {
  if (const auto* rejected = std::get_if<PairRejected>(&event.body)) {
    hints_.insert_or_assign(std::string(event.component.name), std::string(rejected->hint));
  } else if (const auto* fault = std::get_if<FaultEvent>(&event.body)) {
    // The episode ends when a valid pair clears InvalidMac; the Streamer reports the next one.
    if (fault->id == FaultId::InvalidMac && !fault->active) {
      if (const auto found = hints_.find(fault->vehicle); found != hints_.end()) hints_.erase(found);
    }
  }
}

}  // namespace ocp::sim_app
