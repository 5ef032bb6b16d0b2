#pragma once
// Standing rules (case.hpp) applied over a whole run: every case's wire log is scanned for
// every selected case that carries a rule, and the first offending client frame is folded into
// that case's result, so an occasional oversized or malformed frame in any case is caught, not
// only one sent in the second the rule's own case watches.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "conformance/case.hpp"
#include "conformance/wire_log.hpp"

namespace ocp::conformance {

struct StandingHit {
  std::size_t case_index = 0;  // in run order: of two hits the earlier case's is first
  std::string case_id;         // where the frame was sent
  std::int64_t time_us = 0;    // on that case's timeline (µs since its host started)
  StandingFinding finding;
  std::string frame;  // the start of the offending frame's payload
};

// The first frame of `entries` that `rule` finds fault with, or nullopt.
std::optional<StandingHit> first_standing_violation(const StandingRule& rule, const std::vector<WireLogEntry>& entries,
                                                    std::size_t case_index, const std::string& case_id);
// Keeps in `kept` the hit that ranks first: a failure before a NON-STRICT, then the earlier case.
void keep_first_hit(std::optional<StandingHit>& kept, StandingHit hit);
// Folds `hit` into the result of the case that carries the rule: its verdict becomes the
// worse of the two, and the actual names the case, the time and the first offending frame.
void apply_standing_hit(CaseResult& result, const StandingHit& hit);

}  // namespace ocp::conformance
