#pragma once
// The client-side requirements (issue #26): one table per suite, written once as data next to
// the cases (vehicle_requirements.cpp, operator_requirements.cpp). Each row names the cases
// that cover it and the broken clients that fail it; the broken clients must be ones its cases
// name (CaseInfo::broken_by), so every row is proven by a CoverageBrokenClient ctest.
// `ocp_conformance … --list --coverage` prints the table; requirement_problems() is what the
// tests hold it to.
#include <string>
#include <vector>

#include "conformance/case.hpp"

namespace ocp::conformance {

struct Requirement {
  std::string id;                      // "V-3.3-echo-exact": V/O, SPEC section, short name
  std::string text;                    // the requirement, one line
  std::string source;                  // "SPEC §3.3", "seed 000 (Practical connection rules)"
  Tier tier = Tier::must;              // per SPEC §2's Decision: MUST only on what the product can send
  std::vector<std::string> cases;      // case ids that cover it
  std::vector<std::string> broken_by;  // "broken_client.py MODE" / "vehicle_client --misbehave-…"
  std::string not_covered;             // when `cases` is empty: why (a MUST row may not have one)
};

const std::vector<Requirement>& vehicle_requirements();
const std::vector<Requirement>& operator_requirements();

// Every way the table falls short, one line each (empty: none): a MUST requirement with no
// case; a requirement without a case and without a reason; a covered requirement naming no
// broken client, or one its cases do not name; a case id that does not exist; a MUST or SHOULD
// case no requirement covers; a duplicate requirement id.
std::vector<std::string> requirement_problems(const std::vector<Requirement>& requirements,
                                              const std::vector<CaseInfo>& cases);

// --list --coverage: the Markdown table, one row per requirement (requirement, source, tier,
// cases, broken clients with the verdict each gets).
std::string requirement_table(const std::vector<Requirement>& requirements, const std::vector<CaseInfo>& cases);

}  // namespace ocp::conformance
