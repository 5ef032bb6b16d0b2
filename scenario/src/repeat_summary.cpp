// The --repeat summary (reports.hpp): per file, per expectation, how many seeds passed.
#include <map>

#include "scenario/reports.hpp"

namespace ocp::scenario {
namespace {

constexpr std::size_t seeds_listed = 10;   // more would bury the line; the JUnit file has them all

struct Tally {
  std::size_t runs = 0;
  std::vector<std::size_t> passed;                 // per expectation
  std::vector<std::vector<std::uint64_t>> failed;  // per expectation: the seeds
};

std::string seed_list(const std::vector<std::uint64_t>& seeds) {
  std::string out;
  for (std::size_t i = 0; i < seeds.size() && i < seeds_listed; ++i) out += (i == 0 ? "" : ", ") + std::to_string(seeds[i]);
  if (seeds.size() > seeds_listed) out += " and " + std::to_string(seeds.size() - seeds_listed) + " more";
  return out;
}

}  // namespace

std::string repeat_summary(const std::vector<RunReport>& reports) {
  std::vector<const Scenario*> order;   // files in the order they ran
  std::map<const Scenario*, Tally> tallies;
  for (const RunReport& report : reports) {
    if (report.run->interrupted) continue;
    const Scenario* scenario = report.scenario;
    auto [it, inserted] = tallies.try_emplace(scenario);
    Tally& tally = it->second;
    if (inserted) {
      order.push_back(scenario);
      tally.passed.resize(scenario->expectations.size());
      tally.failed.resize(scenario->expectations.size());
    }
    ++tally.runs;
    for (std::size_t i = 0; i < report.verdicts.size() && i < tally.passed.size(); ++i) {
      if (report.verdicts[i].passed) ++tally.passed[i];
      else tally.failed[i].push_back(report.run->seed);
    }
  }
  std::string out;
  for (const Scenario* scenario : order) {
    const Tally& tally = tallies.at(scenario);
    out += "\n" + scenario->path + ": " + std::to_string(tally.runs) + (tally.runs == 1 ? " seed\n" : " seeds\n");
    for (std::size_t i = 0; i < tally.passed.size(); ++i) {
      const bool all = tally.passed[i] == tally.runs;
      out += std::string(all ? "  ✓ " : "  ✗ ") + scenario->expectations[i].title + ": passed " +
             std::to_string(tally.passed[i]) + " of " + std::to_string(tally.runs) + (tally.runs == 1 ? " seed" : " seeds");
      if (!all) out += (tally.failed[i].size() == 1 ? "; failed with seed " : "; failed with seeds ") + seed_list(tally.failed[i]);
      out += "\n";
    }
  }
  return out;
}

}  // namespace ocp::scenario
