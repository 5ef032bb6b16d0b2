#include "ocp/pair_diagnosis.hpp"

#include <fmt/format.h>

#include <array>
#include <cstdint>

namespace ocp {
namespace {

constexpr std::uint64_t two_to_53 = std::uint64_t{1} << 53;
// A double's spacing just below 2^64: no rounding moves a u64 further than this.
constexpr std::uint64_t double_spacing_near_2_to_64 = std::uint64_t{1} << 11;

std::uint64_t distance(std::uint64_t a, std::uint64_t b) { return a > b ? a - b : b - a; }

// Among issued pairs that pass `keep`, the one nearest to `ack_time`.
template <class Keep>
std::optional<AckPair> nearest(std::span<const AckPair> issued, std::uint64_t ack_time, Keep keep) {
  std::optional<AckPair> best;
  for (const AckPair& pair : issued) {
    if (!keep(pair)) continue;
    if (!best || distance(pair.ack_time, ack_time) < distance(best->ack_time, ack_time)) best = pair;
  }
  return best;
}

std::string pair_text(const AckPair& pair) {
  return fmt::format("(ack_time {}, ack_time_mac {})", pair.ack_time, pair.ack_time_mac);
}

}  // namespace

std::string_view pair_cause_name(PairCause cause) {
  switch (cause) {
    case PairCause::rounded_through_double: return "rounded_through_double";
    case PairCause::partial_echo: return "partial_echo";
    case PairCause::mac_altered: return "mac_altered";
    case PairCause::ack_time_altered: return "ack_time_altered";
    case PairCause::not_issued: return "not_issued";
  }
  return "?";
}

PairJudgement judge_altered_pair(const AckPair& altered, std::span<const AckPair> issued) {
  const auto same_mac = [&](const AckPair& p) { return p.ack_time_mac == altered.ack_time_mac; };
  const auto same_ack_time = [&](const AckPair& p) { return p.ack_time == altered.ack_time; };
  const auto rounded_from = [&](const AckPair& p) {
    return same_mac(p) && p.ack_time >= two_to_53 && p.ack_time != altered.ack_time &&
           distance(p.ack_time, altered.ack_time) < double_spacing_near_2_to_64;
  };
  if (auto original = nearest(issued, altered.ack_time, rounded_from)) {
    return {PairCause::rounded_through_double, original};
  }
  const auto with_mac = nearest(issued, altered.ack_time, same_mac);
  if (auto with_ack_time = nearest(issued, altered.ack_time, same_ack_time)) {
    return {with_mac ? PairCause::partial_echo : PairCause::mac_altered, with_ack_time};
  }
  if (with_mac) return {PairCause::ack_time_altered, with_mac};
  return {PairCause::not_issued, nearest(issued, altered.ack_time, [](const AckPair&) { return true; })};
}

std::string describe_rejected_pair(const AckPair& rejected, const PairJudgement& judgement) {
  const std::string got = pair_text(rejected);
  if (!judgement.nearest_issued) return fmt::format("returned pair {} but no pair was issued yet", got);
  const AckPair& issued = *judgement.nearest_issued;
  const std::uint64_t off = distance(issued.ack_time, rejected.ack_time);
  switch (judgement.cause) {
    case PairCause::rounded_through_double:
      return fmt::format("returned pair {}: ack_time differs by {} from issued pair {}: rounded through a double? "
                         "Parse ack_time as an unsigned 64-bit integer and copy it unchanged",
                         got, off, pair_text(issued));
    case PairCause::partial_echo:
      return fmt::format("returned pair {}: the ack_time of issued pair {} with the ack_time_mac of another issued "
                         "pair: a partial echo? Return both fields of the same (latest) pair",
                         got, pair_text(issued));
    case PairCause::mac_altered:
      return fmt::format("returned pair {}: ack_time was issued as {}: MAC altered? Copy ack_time_mac unchanged "
                         "(an unsigned 32-bit integer)",
                         got, pair_text(issued));
    case PairCause::ack_time_altered:
      return fmt::format("returned pair {}: ack_time differs by {} from issued pair {} with the same MAC: ack_time "
                         "altered? Copy it unchanged",
                         got, off, pair_text(issued));
    case PairCause::not_issued:
      return fmt::format("returned pair {}: neither field matches a recently issued pair (nearest {}): a stale pair "
                         "from before a reconnect or a Streamer restart, another vehicle's pair, or made up?",
                         got, pair_text(issued));
  }
  return got;
}

PairDiagnosis diagnose_altered_pairs(const std::vector<AckPair>& altered, const std::vector<AckPair>& sent) {
  // The causes the suite names, by precedence: one rounded pair explains the others it caused.
  constexpr std::array named{PairCause::rounded_through_double, PairCause::partial_echo, PairCause::mac_altered};
  for (const PairCause wanted : named) {
    for (const AckPair& pair : altered) {
      const PairJudgement judgement = judge_altered_pair(pair, sent);
      if (judgement.cause != wanted) continue;
      const AckPair& original = *judgement.nearest_issued;
      switch (wanted) {
        case PairCause::rounded_through_double:
          return {"ack_time rounded through a double: parse it as an unsigned 64-bit integer and copy it byte for byte",
                  fmt::format("{} came back as {} (off by {})", original.ack_time, pair.ack_time,
                              distance(original.ack_time, pair.ack_time))};
        case PairCause::partial_echo:
          return {"a partial echo: ack_time and ack_time_mac taken from different control messages; echo both fields "
                  "of the same (latest) message",
                  fmt::format("ack_time {} with ack_time_mac {}", pair.ack_time, pair.ack_time_mac)};
        default:
          return {"ack_time_mac altered: copy it unchanged (an unsigned 32-bit integer)",
                  fmt::format("ack_time {} was sent, but never with ack_time_mac {}", pair.ack_time,
                              pair.ack_time_mac)};
      }
    }
  }
  return {};
}

}  // namespace ocp
