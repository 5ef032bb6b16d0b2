#include "conformance/verdict.hpp"

namespace ocp::conformance {

std::string_view tier_name(Tier tier) {
  switch (tier) {
    case Tier::must:
      return "MUST";
    case Tier::should:
      return "SHOULD";
    case Tier::info:
      return "INFO";
  }
  return "?";
}

std::string_view verdict_name(Verdict verdict) {
  switch (verdict) {
    case Verdict::ok:
      return "OK";
    case Verdict::non_strict:
      return "NON-STRICT";
    case Verdict::informational:
      return "INFORMATIONAL";
    case Verdict::failed:
      return "FAILED";
  }
  return "?";
}

std::string_view verdict_slug(Verdict verdict) {
  switch (verdict) {
    case Verdict::ok:
      return "ok";
    case Verdict::non_strict:
      return "non-strict";
    case Verdict::informational:
      return "informational";
    case Verdict::failed:
      return "failed";
  }
  return "?";
}

bool parse_verdict(std::string_view text, Verdict& verdict) {
  for (Verdict v : {Verdict::ok, Verdict::non_strict, Verdict::informational, Verdict::failed}) {
    if (text == verdict_name(v) || text == verdict_slug(v)) {
      verdict = v;
      return true;
    }
  }
  return false;
}

}  // namespace ocp::conformance
