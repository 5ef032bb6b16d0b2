#include "conformance/standing_rules.hpp"

#include <fmt/format.h>

namespace ocp::conformance {
namespace {

// How bad a verdict is, for "the worse of two".
int standing_severity(Verdict verdict) {
  switch (verdict) {
    case Verdict::ok:
      return 0;
    case Verdict::informational:
      return 1;
    case Verdict::non_strict:
      return 2;
    case Verdict::failed:
      return 3;
  }
  return 3;
}

constexpr std::size_t standing_frame_excerpt = 200;

}  // namespace

std::optional<StandingHit> first_standing_violation(const StandingRule& rule, const std::vector<WireLogEntry>& entries,
                                                    std::size_t case_index, const std::string& case_id) {
  if (!rule) return std::nullopt;
  std::optional<StandingHit> first;
  for (const WireLogEntry& entry : entries) {
    if (entry.kind != WireEntryKind::in) continue;
    std::optional<StandingFinding> finding = rule(entry);
    if (!finding) continue;
    StandingHit hit{case_index, case_id, entry.time_us, std::move(*finding),
                    entry.text.substr(0, standing_frame_excerpt)};
    if (entry.text.size() > standing_frame_excerpt) hit.frame += fmt::format("… ({} bytes)", entry.text.size());
    if (entry.drained) hit.frame = fmt::format("(drained: length prefix {})", entry.length_prefix);
    // A failure is the first worth naming; a NON-STRICT one only until a failure turns up.
    if (hit.finding.verdict == Verdict::failed) return hit;
    if (!first) first = std::move(hit);
  }
  return first;
}

void keep_first_hit(std::optional<StandingHit>& kept, StandingHit hit) {
  if (!kept) {
    kept = std::move(hit);
    return;
  }
  const int now = standing_severity(kept->finding.verdict), offered = standing_severity(hit.finding.verdict);
  if (offered > now || (offered == now && hit.case_index < kept->case_index)) kept = std::move(hit);
}

void apply_standing_hit(CaseResult& result, const StandingHit& hit) {
  if (standing_severity(hit.finding.verdict) <= standing_severity(result.verdict)) return;
  result.verdict = hit.finding.verdict;
  const std::string where = hit.case_id == result.info.id ? std::string("this case") : "case " + hit.case_id;
  result.actual +=
      fmt::format("; checked on every client frame of the run: {} in {} at {:.1f} ms; first offending frame: {}",
                  hit.finding.problem, where, static_cast<double>(hit.time_us) / 1000.0, hit.frame);
}

}  // namespace ocp::conformance
