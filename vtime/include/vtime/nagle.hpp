#pragma once
// The client's kernel's Nagle algorithm on one OCP connection, in virtual time
// (docs/virtual-time.md, "Nagle's algorithm"). The real loopback socket always has TCP_NODELAY
// (the shim sets it), so its bytes reach the Controller at once; this model decides when they
// are on the wire, as Linux would send them:
//
//   * with TCP_NODELAY (the program's own setting, reported by the shim), at once;
//   * without it, a small segment waits while an earlier one is unacknowledged (Linux's
//     tcp_nagle_check with Minshall's variant; every OCP frame is far below loopback's MSS of
//     65 483 bytes). So the first write at an instant with nothing
//     in flight goes at once, and every later write is held (but for whole segments of a full
//     MSS, which Linux sends whatever is in flight: less than one MSS is ever held);
//   * the simulator acknowledges what it received when it writes to the client (the ACK rides
//     on its next frame) or, writing nothing, after Linux's delayed-ACK minimum of 40 ms; the
//     held bytes then go as one segment, and are in flight in turn;
//   * a close sends what is held (the kernel pushes it out before its FIN).
//
// Offsets count the client's bytes on this connection from its start.
#include <cstdint>
#include <optional>

#include "ocp/time.hpp"

namespace ocp::vtime {

class NagleModel {
 public:
  // Linux's TCP_DELACK_MIN (HZ/25): how long the receiver waits for data to carry its ACK.
  static constexpr Micros delayed_ack{40'000};
  // Loopback's MSS: its MTU of 65 536 bytes less the IP and TCP headers and TCP timestamps.
  static constexpr std::uint64_t loopback_mss = 65'483;

  // The client's bytes up to `written` reached us at `now`; the first write among those not
  // seen before ended at `first_write_end` (0, or one already seen: unknown, taken as one
  // write). Returns the offset up to which they are on the wire.
  std::uint64_t arrived(std::uint64_t written, std::uint64_t first_write_end, bool no_delay, SimTime now);
  // We acknowledged every byte on the wire: the held ones go as one segment. Returns sent().
  std::uint64_t acknowledged(SimTime now);
  // The client closed: everything it wrote goes. Returns sent().
  std::uint64_t closed();

  std::uint64_t sent() const { return sent_; }
  std::uint64_t held() const { return arrived_ - sent_; }
  // When the segment in flight is acknowledged if we write nothing to the client before.
  std::optional<SimTime> delayed_ack_due() const;

 private:
  void send_up_to(std::uint64_t end, SimTime now);

  std::uint64_t arrived_ = 0;   // bytes the client wrote that reached us
  std::uint64_t sent_ = 0;      // of them, on the wire (handed to the simulator)
  std::uint64_t acked_ = 0;     // of them, acknowledged
  SimTime in_flight_since_{};   // when the unacknowledged segment went
};

}  // namespace ocp::vtime
