#include "fault_tracker.hpp"

namespace ocp::streamer {

void FaultTracker::set(FaultId id, bool active) {
  if (faults_.contains(id) == active) return;
  faults_.set(id, active);
  if (active) {
    logger_.warn("fault raised: {} ({})", fault_display(id), fault_identifier(id));
  } else {
    logger_.info("fault cleared: {} ({})", fault_display(id), fault_identifier(id));
  }
  on_change_(id, active);
}

}  // namespace ocp::streamer
