#pragma once
// The broken clients each case names (issue #26), parsed from CaseInfo::broken_by: the
// coverage table of docs/conformance.md (requirements.hpp, one row per requirement) and the
// tests' one run per broken client read them from here. The grammar:
//
//   broken_by   := "never fails (INFO)" | part ( "; " part )*
//   part        := client [ " (" note ")" ]
//   client      := "broken_client.py MODE" | "vehicle_client --misbehave-… [VALUE]"
//   note        := "or " alt ( ", " alt )*   alternatives, graded the same (an alt is a whole
//                                           client, a vehicle_client switch "--…", or a mode
//                                           of the primary's broken_client.py)
//                | "NON-STRICT" …           the verdict it gets (a SHOULD case never FAILS)
//                | "FAILED" …
//                | "with ID[,ID…]"          the run also plays these cases (a standing rule
//                                           catches a frame sent during another case)
//                | anything else            prose, ignored (e.g. "op-disable passes")
// The conformance tests run every parsed client against its case and expect its verdict.
#include <string>
#include <vector>

#include "conformance/case.hpp"

namespace ocp::conformance {

struct BrokenClientRun {
  std::string case_id;
  Tier tier = Tier::must;
  std::string client;   // "broken_client.py MODE" or "vehicle_client ARGS"
  std::string verdict;  // what it must get: "FAILED" or "NON-STRICT"
  std::string cases;    // --cases for the run: the case, plus any "with" cases
};

// Every broken client the case names, each alternative separately.
std::vector<BrokenClientRun> broken_client_runs(const CaseInfo& info);
// --list --broken-clients: one line per run, tab-separated: case id, tier, verdict, cases, client.
std::string broken_client_lines(const std::vector<CaseInfo>& cases);

}  // namespace ocp::conformance
