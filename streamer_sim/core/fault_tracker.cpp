#include "fault_tracker.hpp"

namespace ocp::streamer {

void FaultTracker::set(FaultId id, bool active) {
  const auto index = static_cast<std::size_t>(id);
  if (faults_.contains(id) == active) {
    if (flapping_[index]) {
      FlapSummariser& flaps = *flaps_[index];
      if (auto line = flaps.on_steady(logger_.now())) logger_.warn("{}", *line);
      flapping_[index] = flaps.flapping();
    }
    return;
  }
  std::optional<FlapSummariser>& flaps = flaps_[index];
  faults_.set(id, active);
  reason_ = faults_.fault_reason();
  if (!flaps) flaps.emplace(std::string(fault_identifier(id)));
  const FlapSummariser::Verdict verdict = flaps->on_edge(active, logger_.now());
  flapping_[index] = flaps->flapping();
  if (verdict.log_edge && active) {
    logger_.warn("fault raised: {} ({})", fault_display(id), fault_identifier(id));
  } else if (verdict.log_edge) {
    logger_.info("fault cleared: {} ({})", fault_display(id), fault_identifier(id));
  }
  if (verdict.summary) logger_.warn("{}", *verdict.summary);
  on_change_(id, active);
}

}  // namespace ocp::streamer
