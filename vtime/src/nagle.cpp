// NagleModel (vtime/nagle.hpp).
#include "vtime/nagle.hpp"

#include <algorithm>

namespace ocp::vtime {

std::uint64_t NagleModel::arrived(std::uint64_t written, std::uint64_t first_write_end, bool no_delay, SimTime now) {
  const std::uint64_t seen = arrived_;
  arrived_ = std::max(arrived_, written);
  // Setting TCP_NODELAY pushes what the kernel holds (tcp_push_pending_frames), as does a
  // segment that finds nothing unacknowledged.
  // With it, nothing waits for an ACK, so none is awaited (and no delayed ACK scheduled).
  if (no_delay) {
    sent_ = acked_ = arrived_;
  } else if (acked_ == sent_ && arrived_ > sent_) {
    const bool known = first_write_end > seen && first_write_end <= arrived_;
    send_up_to(known ? first_write_end : arrived_, now);
  }
  // Full-sized segments go whatever is unacknowledged: only a small one waits (Minshall). So
  // less than one MSS is ever held.
  sent_ += held() / loopback_mss * loopback_mss;
  return sent_;
}

std::uint64_t NagleModel::acknowledged(SimTime now) {
  acked_ = sent_;
  if (held() > 0) send_up_to(arrived_, now);
  return sent_;
}

std::uint64_t NagleModel::closed() {
  sent_ = arrived_;
  acked_ = sent_;
  return sent_;
}

std::optional<SimTime> NagleModel::delayed_ack_due() const {
  if (acked_ == sent_) return std::nullopt;
  return in_flight_since_ + delayed_ack;
}

void NagleModel::send_up_to(std::uint64_t end, SimTime now) {
  if (end <= sent_) return;
  sent_ = end;
  in_flight_since_ = now;
}

}  // namespace ocp::vtime
