#include "fault_tracker.hpp"

#include "ocp/invariant.hpp"

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
  // Checked before the listener runs: it may report the change anywhere, and set again.
  OCP_INVARIANT(faults_.contains(id) == active, "a fault is as last set");
  OCP_INVARIANT(flaps_[index].has_value(), "every fault that changed has its flap summariser");
  OCP_INVARIANT_DEEP(reason_ == faults_.fault_reason(), "fault_reason lists exactly the active faults");
  on_change_(id, active);
}

}  // namespace ocp::streamer
