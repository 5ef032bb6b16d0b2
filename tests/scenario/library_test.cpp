// Every scenario in scenario/library parses and passes (the ctest scenario_library runs the
// tool on the same folder; this one says which expectation failed inside the test log).
#include <filesystem>
#include <set>

#include "scenario/parse.hpp"
#include "scenario_test_support.hpp"

namespace ocp::scenario {
namespace {

TEST(ScenarioLibrary, EveryFileParsesAndPasses) {
  std::size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(OCP_SCENARIO_LIBRARY_DIR)) {
    if (entry.path().extension() != ".yaml") continue;
    ++files;
    const Scenario scenario = load_scenario(entry.path().string());
    RunOptions options;
    options.trace = false;
    const RunResult run = run_scenario(scenario, options);
    for (const Verdict& verdict : evaluate(scenario, run)) {
      EXPECT_TRUE(verdict.passed) << entry.path() << ": " << verdict.title << "\n  expected " << verdict.expected
                                  << "\n  actual   " << verdict.actual << "\n  reproduce with seed " << run.seed;
    }
  }
  EXPECT_GE(files, 8u);
}

// Across the library every SPEC §6 fault is raised and cleared at least once.
TEST(ScenarioLibrary, EveryFaultRaisedAndCleared) {
  std::set<FaultId> raised, cleared;
  for (const auto& entry : std::filesystem::directory_iterator(OCP_SCENARIO_LIBRARY_DIR)) {
    if (entry.path().extension() != ".yaml") continue;
    const Scenario scenario = load_scenario(entry.path().string());
    RunOptions options;
    options.trace = false;
    const RunResult run = run_scenario(scenario, options);
    for (const auto& [key, intervals] : run.observations.faults) {
      for (const Interval& interval : intervals) {
        if (interval.start > SimTime{0}) raised.insert(key.second);
        if (interval.end) cleared.insert(key.second);
      }
    }
  }
  for (std::size_t i = 0; i < fault_count; ++i) {
    const auto id = static_cast<FaultId>(i);
    EXPECT_TRUE(raised.count(id)) << fault_identifier(id) << " never raised by the library";
    EXPECT_TRUE(cleared.count(id)) << fault_identifier(id) << " never cleared by the library";
  }
}

}  // namespace
}  // namespace ocp::scenario
