#include "control_inbox.hpp"

#include "ocp/invariant.hpp"

namespace ocp::streamer {

bool ControlInbox::push(OperatorControl&& message, SimTime now) {
  bool kept_all = true;
  if (queue_.size() >= hard_limit_items) {
    queue_.pop_front();
    kept_all = false;
  }
  queue_.push_back(QueuedControl{std::move(message), now});
  OCP_INVARIANT(queue_.size() <= hard_limit_items, "the control inbox is bounded: the oldest message makes room");
  return kept_all;
}

QueuedControl ControlInbox::pop() {
  QueuedControl front = std::move(queue_.front());
  queue_.pop_front();
  return front;
}

bool ControlInbox::slow(SimTime now, std::size_t limit, Micros max_age) const {
  if (queue_.empty()) return false;
  return queue_.size() > limit || now - queue_.front().arrived_at > max_age;
}

}  // namespace ocp::streamer
