#include "conformance/coverage.hpp"

#include <fmt/format.h>

namespace ocp::conformance {
namespace {

// Splits at `separator` outside parentheses.
std::vector<std::string> split_outside_parentheses(const std::string& text, const std::string& separator) {
  std::vector<std::string> parts;
  int depth = 0;
  std::size_t start = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '(') ++depth;
    if (text[i] == ')') --depth;
    if (depth == 0 && text.compare(i, separator.size(), separator) == 0) {
      parts.push_back(text.substr(start, i - start));
      start = i + separator.size();
    }
  }
  parts.push_back(text.substr(start));
  return parts;
}

bool coverage_starts_with(const std::string& text, const std::string& prefix) { return text.rfind(prefix, 0) == 0; }

// An alternative named in "(or …)": a switch of the primary client's program, or a mode.
std::string alternative_client(const std::string& primary, const std::string& alt) {
  if (coverage_starts_with(alt, "vehicle_client ") || coverage_starts_with(alt, "broken_client.py ")) return alt;
  if (coverage_starts_with(alt, "--")) return "vehicle_client " + alt;
  if (coverage_starts_with(primary, "broken_client.py ")) return "broken_client.py " + alt;
  return alt;
}

void add_broken_client_part(const CaseInfo& info, const std::string& part, std::vector<BrokenClientRun>& runs) {
  const auto open = part.find(" (");
  std::string client = part.substr(0, open);
  while (!client.empty() && client.back() == ' ') client.pop_back();
  const std::string note = open == std::string::npos ? std::string() : part.substr(open + 2, part.size() - open - 3);
  BrokenClientRun run{info.id, info.tier, client, info.tier == Tier::must ? "FAILED" : "NON-STRICT", info.id};
  if (coverage_starts_with(note, "NON-STRICT")) run.verdict = "NON-STRICT";
  if (coverage_starts_with(note, "FAILED")) run.verdict = "FAILED";
  if (coverage_starts_with(note, "with ")) run.cases += "," + note.substr(5);
  std::vector<std::string> clients{client};
  if (coverage_starts_with(note, "or ")) {
    for (const std::string& alt : split_outside_parentheses(note.substr(3), ", "))
      clients.push_back(alternative_client(client, alt));
  }
  for (const std::string& c : clients) {
    if (!coverage_starts_with(c, "broken_client.py ") && !coverage_starts_with(c, "vehicle_client ")) continue;
    run.client = c;
    runs.push_back(run);
  }
}

}  // namespace

std::vector<BrokenClientRun> broken_client_runs(const CaseInfo& info) {
  std::vector<BrokenClientRun> runs;
  for (const std::string& part : split_outside_parentheses(info.broken_by, "; "))
    add_broken_client_part(info, part, runs);
  return runs;
}

std::string broken_client_lines(const std::vector<CaseInfo>& cases) {
  std::string out;
  for (const CaseInfo& info : cases) {
    for (const BrokenClientRun& run : broken_client_runs(info)) {
      out += fmt::format("{}\t{}\t{}\t{}\t{}\n", run.case_id, tier_name(run.tier), run.verdict, run.cases, run.client);
    }
  }
  return out;
}

}  // namespace ocp::conformance
