#pragma once
// The Streamer's vehicle-side fault set. Faults are self-recovering (SPEC §6): callers state
// each condition every time they evaluate it; the tracker logs a raise or a clear once, with
// the display string, and tells the observer. The observer hears every edge; the log
// summarises a flapping fault instead of repeating it (flap_summariser.hpp).
#include <map>

#include "ocp/faults.hpp"
#include "ocp/flap_summariser.hpp"
#include "ocp/log.hpp"
#include "streamer/streamer_core.hpp"

namespace ocp::streamer {

class FaultTracker {
 public:
  explicit FaultTracker(const Logger& logger) : logger_(logger) {}

  void set_observer(StreamerObserver* observer) { observer_ = observer; }
  // Records the current truth of one condition; logs and notifies only on a change.
  void set(FaultId id, bool active);
  const FaultSet& faults() const { return faults_; }

 private:
  Logger logger_;
  StreamerObserver* observer_ = nullptr;
  FaultSet faults_;
  std::map<FaultId, FlapSummariser> flaps_;  // per fault, from its first edge on
};

}  // namespace ocp::streamer
