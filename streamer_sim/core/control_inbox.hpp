#pragma once
// The internal queue between the com channel and the control path (SPEC §6
// ControlThreadChannelSlow). Normally drained as soon as a message arrives; a test can stall
// the drain to let it back up. Bounded: beyond `hard_limit_items` the oldest is dropped.
#include <cstddef>
#include <deque>

#include "ocp/link_messages.hpp"
#include "ocp/time.hpp"

namespace ocp::streamer {

struct QueuedControl {
  OperatorControl message;
  SimTime arrived_at;
};

class ControlInbox {
 public:
  static constexpr std::size_t hard_limit_items = 4096;

  // Returns false when the oldest message had to be dropped to stay within the hard limit.
  bool push(OperatorControl&& message, SimTime now);
  bool empty() const { return queue_.empty(); }
  std::size_t size() const { return queue_.size(); }
  QueuedControl pop();
  void clear() { queue_.clear(); }

  // True while backlog > limit or the oldest queued message is older than max_age.
  bool slow(SimTime now, std::size_t limit, Micros max_age) const;

 private:
  std::deque<QueuedControl> queue_;
};

}  // namespace ocp::streamer
