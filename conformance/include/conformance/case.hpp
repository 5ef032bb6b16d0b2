#pragma once
// One conformance case: a stable id tied to a SPEC / seed section, the requirement quoted from
// the source, a tier, a timeout, every accepted outcome, and the body that plays it.
#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "conformance/verdict.hpp"
#include "conformance/wire_log.hpp"

namespace ocp::conformance {

class CaseContext;

struct CaseInfo {
  std::string id;           // "vehicle/3.3/1": <suite>/<SPEC section>/<n>; never renumbered
  std::string title;        // one line
  std::string source;       // where the requirement is quoted from ("SPEC §3.3", "seed 000")
  std::string requirement;  // the quoted requirement
  Tier tier = Tier::must;
  std::chrono::milliseconds timeout{10'000};  // whole case, before --timeout-scale
  std::vector<std::string> expected;          // every accepted outcome, "OK: …", "NON-STRICT: …"
  std::string broken_by;                      // a client that fails it (for docs and the tests)
};

struct Outcome {
  Verdict verdict = Verdict::failed;
  std::string actual;  // what was observed, with numbers
  std::string cause;   // the named cause behind it, when one was found (ocp/pair_diagnosis.hpp)
};

// A standing rule (issue #26): a requirement on every frame the client sends, in every case,
// for the whole run (valid frames ≤ 16 KiB, the response schema). The runner applies it to each
// case's wire log (standing_rules.hpp); the first offending frame found anywhere is reported
// under the id of the case that carries the rule.
struct StandingFinding {
  Verdict verdict = Verdict::failed;
  std::string problem;  // what is wrong with the frame
};
// nullopt: the entry is fine (or not a client frame).
using StandingRule = std::function<std::optional<StandingFinding>(const WireLogEntry&)>;

struct Case {
  CaseInfo info;
  std::function<Outcome(CaseContext&)> run;  // starts once the client is connected (runner.cpp)
  StandingRule standing = {};  // empty: the case grades only its own window
};

struct CaseResult {
  CaseInfo info;
  Verdict verdict = Verdict::failed;
  std::string actual;
  std::string cause;  // Outcome::cause
  double duration_ms = 0.0;
  std::vector<WireLogEntry> wire_log;  // kept for every case that is not OK
  std::string client_log_path;         // the launched client's output, when launched
};

}  // namespace ocp::conformance
