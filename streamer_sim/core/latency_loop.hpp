#pragma once
// The Streamer's half of the latency loop (SPEC §5): issues a fresh MAC'd ack pair per
// control message, validates returned pairs in constant time, and measures latency from the
// newest valid pair, re-evaluated at whatever `now` it is asked about.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "ocp/mac.hpp"
#include "ocp/messages.hpp"
#include "ocp/pair_diagnosis.hpp"
#include "ocp/time.hpp"

namespace ocp::streamer {

enum class ReturnedPairCheck { valid, invalid, missing };

class LatencyLoop {
 public:
  LatencyLoop(const MacKey& key, std::uint64_t ack_time_offset);

  // ack_time counts from here: elapsed µs since `start_time` plus the offset.
  void start(SimTime start_time) { start_time_ = start_time; }

  [[nodiscard]] AckPair issue(SimTime now);
  // Validates a returned pair; a valid one newer than the newest so far becomes the newest.
  [[nodiscard]] ReturnedPairCheck check_returned(const std::optional<AckPair>& returned, SimTime now);

  // A rejected pair against the pairs issued lately (the last kept_issued_pairs): its likely
  // cause and the issued pair nearest to it. Runs once per InvalidMac episode, not per message.
  [[nodiscard]] PairJudgement judge_rejected(const AckPair& rejected) const;

  // 2.56 s of pairs at 100 Hz: a returned pair older than that is stale anyway (HighLatency at
  // 500 ms), and 4 KiB a Streamer stays small in a fleet of thousands.
  static constexpr std::size_t kept_issued_pairs = 256;

  // now − issue time of the newest valid pair; nullopt before any valid pair.
  [[nodiscard]] std::optional<Micros> latency(SimTime now) const;
  [[nodiscard]] std::optional<std::uint64_t> latency_ms(SimTime now) const;
  // now − when the newest valid pair came back; nullopt before any valid pair.
  [[nodiscard]] std::optional<Micros> newest_pair_age(SimTime now) const;

 private:
  AckMac mac_;
  std::uint64_t ack_time_offset_;
  SimTime start_time_{};
  // Elapsed µs since start at which the newest valid returned pair was issued. Kept as u64
  // arithmetic on ack_time (never a double): offsets ≥ 2^53 stay exact.
  std::optional<std::uint64_t> newest_valid_elapsed_us_;
  std::optional<std::uint64_t> last_issued_elapsed_us_;   // for the issue-order invariant
  SimTime newest_valid_arrived_at_{};
  // The pairs issued lately, a ring: issued_count_ % kept_issued_pairs is the next slot.
  std::array<AckPair, kept_issued_pairs> recent_issued_{};
  std::uint64_t issued_count_ = 0;
};

}  // namespace ocp::streamer
