#pragma once
// The drop-tail queue in front of a trace-driven link direction (as Mahimahi's
// --uplink-queue=droptail). A message is cut into DeliveryTrace::packet_bytes packets; each
// delivery opportunity carries one packet; the message leaves the queue with its last packet.
// Computed, not ticked: each message is given its opportunities when it is queued, so a quiet
// link costs nothing and a message costs O(log trace length).
#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>

#include "ocp/delivery_trace.hpp"
#include "ocp/time.hpp"

namespace ocp {

class TraceQueue {
 public:
  // 0 = no limit of that kind; with neither, `default_limit_packets` applies (everything that
  // grows has a limit).
  struct Limits {
    std::size_t bytes = 0;
    std::size_t packets = 0;
  };
  static constexpr std::size_t default_limit_packets = 1000;

  // Starts `trace` at `start` (its opportunity times count from there) with an empty queue.
  void reset(std::shared_ptr<const DeliveryTrace> trace, SimTime start);
  const std::shared_ptr<const DeliveryTrace>& trace_shared() const { return trace_; }
  // When the message's last packet is delivered, or nullopt when it does not fit the queue.
  std::optional<SimTime> enqueue(SimTime now, std::size_t size_bytes, Limits limits);
  // What waits at `now`: packets whose opportunity lies after `now`.
  std::size_t queued_packets(SimTime now) const;
  std::size_t queued_bytes(SimTime now);

  static std::uint64_t packets_of(std::size_t size_bytes) {
    return size_bytes == 0 ? 1 : (size_bytes + DeliveryTrace::packet_bytes - 1) / DeliveryTrace::packet_bytes;
  }

 private:
  std::uint64_t served_by(SimTime now) const;  // opportunities used up by `now`
  std::size_t packets_after(std::uint64_t served) const;
  std::size_t bytes_after(std::uint64_t served);  // also forgets messages fully served
  struct Queued {
    std::uint64_t first = 0;  // its packets ride opportunities first..last
    std::uint64_t last = 0;
    std::size_t bytes = 0;
  };
  std::shared_ptr<const DeliveryTrace> trace_;
  SimTime start_{};
  std::uint64_t next_free_ = 0;   // the first opportunity no packet has claimed
  std::deque<Queued> queued_;     // messages not fully delivered, oldest first
  std::size_t queued_total_bytes_ = 0;  // sum of queued_[i].bytes
};

}  // namespace ocp
