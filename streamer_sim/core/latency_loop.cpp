#include "latency_loop.hpp"

#include "ocp/invariant.hpp"
#include "ocp/mutants.hpp"

#include <span>

namespace ocp::streamer {

LatencyLoop::LatencyLoop(const MacKey& key, std::uint64_t ack_time_offset)
    : mac_(key), ack_time_offset_(ack_time_offset) {}

AckPair LatencyLoop::issue(SimTime now) {
  const auto elapsed_us = static_cast<std::uint64_t>((now - start_time_).count());
  // Unsigned wrap-around is intended: the offset is opaque, subtraction undoes it exactly.
  const std::uint64_t ack_time = elapsed_us + ack_time_offset_;
  // Pairs are told apart, and the newest valid one found, by their issue time alone.
  OCP_INVARIANT(!last_issued_elapsed_us_ || elapsed_us > *last_issued_elapsed_us_,
                "ack pairs are issued in strictly increasing order (one per control tick)");
  last_issued_elapsed_us_ = elapsed_us;
  const AckPair pair{ack_time, mac_.compute(ack_time)};
  recent_issued_[issued_count_++ % kept_issued_pairs] = pair;
  OCP_INVARIANT(pair.ack_time - ack_time_offset_ == elapsed_us, "an issued ack_time undoes to its issue time exactly");
  OCP_INVARIANT(issued_count_ > 0 && recent_issued_[(issued_count_ - 1) % kept_issued_pairs] == pair,
                "the pair issued now is the newest kept for judging rejected pairs");
  return pair;
}

PairJudgement LatencyLoop::judge_rejected(const AckPair& rejected) const {
  const std::size_t kept = issued_count_ < kept_issued_pairs ? static_cast<std::size_t>(issued_count_) : kept_issued_pairs;
  return judge_altered_pair(rejected, std::span<const AckPair>(recent_issued_.data(), kept));
}

ReturnedPairCheck LatencyLoop::check_returned(const std::optional<AckPair>& returned, SimTime now) {
  if (!returned) return ReturnedPairCheck::missing;
  if (!mac_.verify(returned->ack_time, returned->ack_time_mac)) return ReturnedPairCheck::invalid;
  const std::uint64_t issued_elapsed_us = returned->ack_time - ack_time_offset_;
  // A reordered older pair must not make the loop look faster than the newest one.
  bool newer = !newest_valid_elapsed_us_ || issued_elapsed_us > *newest_valid_elapsed_us_;
#ifdef OCP_MUTANTS
  if (mutant_active(Mutant::stale_pair_accepted)) newer = true;
#endif
  const std::optional<std::uint64_t> newest_before = newest_valid_elapsed_us_;
  if (newer) {
    newest_valid_elapsed_us_ = issued_elapsed_us;
    newest_valid_arrived_at_ = now;
  }
  OCP_INVARIANT(!newest_before || *newest_valid_elapsed_us_ >= *newest_before || OCP_MUTATED(stale_pair_accepted),
                "the newest valid pair is never older than the one before it");
  return ReturnedPairCheck::valid;
}

std::optional<Micros> LatencyLoop::latency(SimTime now) const {
  if (!newest_valid_elapsed_us_) return std::nullopt;
  const auto elapsed_us = static_cast<std::uint64_t>((now - start_time_).count());
  // A valid MAC means we issued it, so it cannot be from the future; guard anyway.
  if (*newest_valid_elapsed_us_ > elapsed_us) return Micros{0};
  return Micros{static_cast<std::int64_t>(elapsed_us - *newest_valid_elapsed_us_)};
}

std::optional<Micros> LatencyLoop::newest_pair_age(SimTime now) const {
  if (!newest_valid_elapsed_us_) return std::nullopt;
  return now - newest_valid_arrived_at_;
}

std::optional<std::uint64_t> LatencyLoop::latency_ms(SimTime now) const {
  const auto value = latency(now);
  if (!value) return std::nullopt;
  return static_cast<std::uint64_t>(to_whole_ms(*value));
}

}  // namespace ocp::streamer
