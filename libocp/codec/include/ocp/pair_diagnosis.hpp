#pragma once
// One bug, one named cause: what a client did to an ack pair that was never issued. The rule
// lives here, once, for both who judge echoed pairs:
//  * the conformance suite (diagnose_altered_pairs): a client that reads ack_time as a double
//    fails many cases at once; each of those cases shows the cause, the report names it once;
//  * the Streamer (judge_altered_pair, describe_rejected_pair): on the first InvalidMac of an
//    episode it logs the rejected pair, the nearest pair it issued and a hint.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "ocp/messages.hpp"

namespace ocp {

// Why a pair that was never issued came back, judged against the pairs that were issued.
enum class PairCause : std::uint8_t {
  rounded_through_double,  // the MAC of an issued pair ≥ 2^53 with an ack_time < 2^11 from it
  partial_echo,            // ack_time of one issued pair with the ack_time_mac of another
  mac_altered,             // an issued ack_time with a MAC that was never issued
  ack_time_altered,        // the MAC of an issued pair with an ack_time no double rounds to
  not_issued,              // neither field was issued (another Streamer's pair, or made up)
};
std::string_view pair_cause_name(PairCause cause);   // "rounded_through_double", …

struct PairJudgement {
  PairCause cause = PairCause::not_issued;
  // The issued pair it most likely came from: the one sharing a field with it, else the one
  // nearest in ack_time; nullopt only when nothing was issued.
  std::optional<AckPair> nearest_issued;
};

// One altered pair against the issued ones (any order).
PairJudgement judge_altered_pair(const AckPair& altered, std::span<const AckPair> issued);

// One line for a person, naming the nearest issued pair and the likely cause, e.g.
// "ack_time differs by 1 from issued pair (ack_time 9007199254740993, ack_time_mac 42):
//  rounded through a double? …".
std::string describe_rejected_pair(const AckPair& rejected, const PairJudgement& judgement);

struct PairDiagnosis {
  std::string cause;     // the same text for every case it shows in: the report names it once
  std::string example;   // one altered pair of this case against the pair it came from
};

// The likeliest cause behind `altered` (pairs the client echoed that were never sent), judged
// against every pair that was sent, in this order of precedence: rounded through a double, a
// partial echo, an altered MAC. An empty cause when none of them fits.
PairDiagnosis diagnose_altered_pairs(const std::vector<AckPair>& altered, const std::vector<AckPair>& sent);

}  // namespace ocp
