#include "ocp/trace_queue.hpp"

#include <algorithm>

#include "ocp/invariant.hpp"

namespace ocp {

void TraceQueue::reset(std::shared_ptr<const DeliveryTrace> trace, SimTime start) {
  trace_ = std::move(trace);
  start_ = start;
  next_free_ = 0;
  queued_.clear();
  queued_total_bytes_ = 0;
  OCP_INVARIANT(queued_.empty() && queued_total_bytes_ == 0, "a reset queue holds nothing");
}

std::uint64_t TraceQueue::served_by(SimTime now) const {
  // An opportunity at exactly `now` has already carried its packet away.
  return trace_->first_at_or_after(now - start_ + Micros{1});
}

std::size_t TraceQueue::queued_packets(SimTime now) const {
  if (!trace_) return 0;
  return packets_after(served_by(now));
}

std::size_t TraceQueue::packets_after(std::uint64_t served) const {
  return next_free_ > served ? static_cast<std::size_t>(next_free_ - served) : 0;
}

std::size_t TraceQueue::queued_bytes(SimTime now) {
  if (!trace_) return 0;
  return bytes_after(served_by(now));
}

std::size_t TraceQueue::bytes_after(std::uint64_t served) {
  while (!queued_.empty() && queued_.front().last < served) {
    queued_total_bytes_ -= queued_.front().bytes;
    queued_.pop_front();
  }
  OCP_INVARIANT(!queued_.empty() || queued_total_bytes_ == 0, "an empty trace queue counts no bytes");
  if (queued_.empty()) return 0;
  const Queued& front = queued_.front();
  const std::size_t gone = front.first < served
                               ? std::min(front.bytes, static_cast<std::size_t>(served - front.first) * DeliveryTrace::packet_bytes)
                               : 0;
  return queued_total_bytes_ - gone;
}

std::optional<SimTime> TraceQueue::enqueue(SimTime now, std::size_t size_bytes, Limits limits) {
  const std::uint64_t packets = packets_of(size_bytes);
  if (limits.bytes == 0 && limits.packets == 0) limits.packets = default_limit_packets;
  // One look-up of the timetable per message: what has left by now (also forgets it, so the
  // deque stays within the limit) and where this message's packets start.
  const std::uint64_t served = served_by(now);
  const std::size_t bytes_waiting = bytes_after(served);
  if (limits.packets > 0 && packets_after(served) + packets > limits.packets) return std::nullopt;
  if (limits.bytes > 0 && bytes_waiting + size_bytes > limits.bytes) return std::nullopt;
  // The first free opportunity at or after now: unclaimed ones exactly at now still count.
  std::uint64_t first = std::max(next_free_, served);
  while (first > next_free_ && trace_->time_of(first - 1) == now - start_) --first;
  const std::uint64_t last = first + packets - 1;
  next_free_ = last + 1;
  queued_.push_back(Queued{first, last, size_bytes});
  queued_total_bytes_ += size_bytes;
  OCP_INVARIANT(last >= first && packets >= 1, "a message takes at least one opportunity, in order");
  OCP_INVARIANT(queued_.empty() || queued_.back().last + 1 == next_free_,
                "the newest queued message ends just before the next free opportunity");
  OCP_INVARIANT(limits.packets == 0 || packets_after(served) <= limits.packets,
                "a trace queue never holds more packets than its limit");
  OCP_INVARIANT(start_ + trace_->time_of(last) >= now, "a message leaves no earlier than it was queued");
  return start_ + trace_->time_of(last);
}

}  // namespace ocp
