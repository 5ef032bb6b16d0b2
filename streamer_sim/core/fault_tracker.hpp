#pragma once
// The Streamer's vehicle-side fault set. Faults are self-recovering (SPEC §6): callers state
// each condition every time they evaluate it; the tracker logs a raise or a clear once, with
// the display string, and publishes a FaultEvent. Subscribers see every edge; the log
// summarises a flapping fault instead of repeating it (flap_summariser.hpp).
#include <array>
#include <bitset>
#include <functional>
#include <optional>
#include <string>

#include "ocp/faults.hpp"
#include "ocp/flap_summariser.hpp"
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
  // faults().fault_reason(), kept up to date on every edge: the control tick sends it 100
  // times a second and it changes rarely, so it is not rebuilt (and allocated) per tick.
  const std::string& reason() const { return reason_; }

 private:
  Logger logger_;
  OnChange on_change_;
  FaultSet faults_;
  std::string reason_;
  // Per fault, from its first edge on; an array because set() runs for every fault every tick.
  std::array<std::optional<FlapSummariser>, fault_count> flaps_;
  // Which summarisers are flapping, mirrored after every call into them: the steady case (no
  // edge, not flapping — nearly every call) then reads one word instead of a cold summariser.
  std::bitset<fault_count> flapping_;
};

}  // namespace ocp::streamer
