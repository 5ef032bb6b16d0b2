#pragma once
// The Streamer's vehicle-side fault set. Faults are self-recovering (SPEC §6): callers state
// each condition every time they evaluate it; the tracker logs a raise or a clear once, with
// the display string, and publishes a FaultEvent.
#include <functional>

#include "ocp/faults.hpp"
#include "ocp/log.hpp"

namespace ocp::streamer {

class FaultTracker {
 public:
  using OnChange = std::function<void(FaultId id, bool active)>;
  FaultTracker(const Logger& logger, OnChange on_change)
      : logger_(logger), on_change_(std::move(on_change)) {}

  // Records the current truth of one condition; logs and reports only on a change.
  void set(FaultId id, bool active);
  const FaultSet& faults() const { return faults_; }

 private:
  Logger logger_;
  OnChange on_change_;
  FaultSet faults_;
};

}  // namespace ocp::streamer
