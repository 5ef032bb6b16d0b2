#include "fault_tracker.hpp"

namespace ocp::streamer {

void FaultTracker::set(FaultId id, bool active) {
  if (faults_.contains(id) == active) {
    if (const auto found = flaps_.find(id); found != flaps_.end() && found->second.flapping()) {
      if (auto line = found->second.on_steady(logger_.now())) logger_.warn("{}", *line);
    }
    return;
  }
  faults_.set(id, active);
  auto flaps = flaps_.try_emplace(id, std::string(fault_identifier(id))).first;
  const FlapSummariser::Verdict verdict = flaps->second.on_edge(active, logger_.now());
  if (verdict.log_edge && active) {
    logger_.warn("fault raised: {} ({})", fault_display(id), fault_identifier(id));
  } else if (verdict.log_edge) {
    logger_.info("fault cleared: {} ({})", fault_display(id), fault_identifier(id));
  }
  if (verdict.summary) logger_.warn("{}", *verdict.summary);
  if (observer_ != nullptr) observer_->on_fault_changed(id, active);
}

}  // namespace ocp::streamer
