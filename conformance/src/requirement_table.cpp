#include <fmt/format.h>

#include <algorithm>
#include <set>

#include "conformance/coverage.hpp"
#include "conformance/requirements.hpp"

namespace ocp::conformance {
namespace {

const CaseInfo* requirement_find_case(const std::vector<CaseInfo>& cases, const std::string& id) {
  for (const CaseInfo& info : cases) {
    if (info.id == id) return &info;
  }
  return nullptr;
}

// Every broken-client run of the requirement's cases.
std::vector<BrokenClientRun> requirement_runs(const Requirement& requirement, const std::vector<CaseInfo>& cases) {
  std::vector<BrokenClientRun> runs;
  for (const std::string& id : requirement.cases) {
    if (const CaseInfo* info = requirement_find_case(cases, id)) {
      for (const BrokenClientRun& run : broken_client_runs(*info)) runs.push_back(run);
    }
  }
  return runs;
}

bool requirement_run_names(const std::vector<BrokenClientRun>& runs, const std::string& client) {
  return std::any_of(runs.begin(), runs.end(), [&](const BrokenClientRun& run) { return run.client == client; });
}

void check_one_requirement(const Requirement& r, const std::vector<CaseInfo>& cases,
                           std::vector<std::string>& problems) {
  if (r.cases.empty()) {
    if (r.tier == Tier::must) problems.push_back(fmt::format("{} (MUST) has no case", r.id));
    if (r.not_covered.empty()) problems.push_back(fmt::format("{} has no case and does not say why", r.id));
    return;
  }
  for (const std::string& id : r.cases) {
    if (requirement_find_case(cases, id) == nullptr)
      problems.push_back(fmt::format("{} names case {}, which does not exist", r.id, id));
  }
  if (r.broken_by.empty()) problems.push_back(fmt::format("{} names no broken client that fails it", r.id));
  const auto runs = requirement_runs(r, cases);
  for (const std::string& client : r.broken_by) {
    if (!requirement_run_names(runs, client)) {
      problems.push_back(
          fmt::format("{}: `{}` is not a broken client of its cases (so no test runs it)", r.id, client));
    }
  }
}

// Each broken client with the verdict it gets on the requirement's case (and its run's companion cases).
std::string requirement_client_cell(const Requirement& r, const std::vector<CaseInfo>& cases) {
  const auto runs = requirement_runs(r, cases);
  std::string cell;
  for (const std::string& client : r.broken_by) {
    std::string verdict = "not run";
    for (const BrokenClientRun& run : runs) {
      if (run.client != client) continue;
      verdict = fmt::format("{} on `{}`{}", run.verdict, run.case_id,
                            run.cases == run.case_id ? "" : ", with " + run.cases.substr(run.case_id.size() + 1));
      break;
    }
    cell += fmt::format("{}`{}` ({})", cell.empty() ? "" : "<br>", client, verdict);
  }
  return cell.empty() ? "**none**" : cell;
}

}  // namespace

std::vector<std::string> requirement_problems(const std::vector<Requirement>& requirements,
                                              const std::vector<CaseInfo>& cases) {
  std::vector<std::string> problems;
  std::set<std::string> ids, covered;
  for (const Requirement& r : requirements) {
    if (!ids.insert(r.id).second) problems.push_back(fmt::format("{} is listed twice", r.id));
    check_one_requirement(r, cases, problems);
    covered.insert(r.cases.begin(), r.cases.end());
  }
  for (const CaseInfo& info : cases) {
    if (info.tier != Tier::info && covered.count(info.id) == 0)
      problems.push_back(fmt::format("case {} covers no requirement", info.id));
  }
  return problems;
}

std::string requirement_table(const std::vector<Requirement>& requirements, const std::vector<CaseInfo>& cases) {
  std::string out =
      "| id | requirement | source | tier | cases | broken client that fails it (verdict on case) "
      "|\n|---|---|---|---|---|---|\n";
  for (const Requirement& r : requirements) {
    std::string case_cell;
    for (const std::string& id : r.cases) case_cell += fmt::format("{}`{}`", case_cell.empty() ? "" : ", ", id);
    const std::string clients = r.cases.empty() ? "not covered: " + r.not_covered : requirement_client_cell(r, cases);
    out += fmt::format("| `{}` | {} | {} | {} | {} | {} |\n", r.id, r.text, r.source, tier_name(r.tier),
                       case_cell.empty() ? "—" : case_cell, clients);
  }
  return out;
}

}  // namespace ocp::conformance
