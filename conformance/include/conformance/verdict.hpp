#pragma once
// Tiers (how binding a requirement is) and verdicts (how a client fared against it).
#include <string_view>

namespace ocp::conformance {

enum class Tier { must, should, info };
// OK: as required. NON-STRICT: works, but not the way the requirement prefers (e.g. echoes on
// its own timer instead of at once). INFORMATIONAL: an INFO case's observation, never a fail.
// FAILED: the requirement is broken.
enum class Verdict { ok, non_strict, informational, failed };

std::string_view tier_name(Tier tier);                        // "MUST" | "SHOULD" | "INFO"
std::string_view verdict_name(Verdict verdict);               // "OK" | "NON-STRICT" | "INFORMATIONAL" | "FAILED"
std::string_view verdict_slug(Verdict verdict);               // "ok" | "non-strict" | … (CSS classes, baselines)
bool parse_verdict(std::string_view text, Verdict& verdict);  // name or slug

}  // namespace ocp::conformance
