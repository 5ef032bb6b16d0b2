#pragma once
// One bug, one named cause: what a client did to the ack pairs it echoed that nobody sent.
// A client that reads ack_time as a double fails many cases at once (every case that checks
// an echoed pair, under names such as "split at every byte boundary"); each of those cases
// shows the cause, and the report names it once.
#include <string>
#include <vector>

#include "ocp/messages.hpp"

namespace ocp::conformance {

struct PairDiagnosis {
  std::string cause;     // the same text for every case it shows in: the report names it once
  std::string example;   // one altered pair of this case against the pair it came from
};

// The likeliest cause behind `altered` (pairs the client echoed that were never sent), judged
// against every pair that was sent; an empty cause when none of the named causes fits.
//  * rounded through a double: the MAC of a sent pair whose ack_time ≥ 2^53, with an ack_time
//    that differs from it by less than 2^11 (a double's spacing below 2^64);
//  * a partial echo: ack_time of one sent pair with the ack_time_mac of another;
//  * an altered MAC: ack_time of a sent pair with a MAC that was never sent.
PairDiagnosis diagnose_altered_pairs(const std::vector<AckPair>& altered, const std::vector<AckPair>& sent);

}  // namespace ocp::conformance
