// A long run's memory is flat (issue #36, "a ceiling on one run"): what grows with simulated
// time is bounded (the series, series.hpp) or streamed (the trace, to its file as the run
// goes). Checked on the observations of a half-hour run, on the trace file, and on the peak
// resident memory of ocp_scenario itself: a long run must not need more than a short one.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "peak_rss.hpp"
#include "scenario/metrics.hpp"
#include "scenario/series.hpp"
#include "scenario_test_support.hpp"
#include "scratch_dir.hpp"

namespace ocp::scenario {
namespace {

using testing_support::memory_is_measurable;
using testing_support::run_measuring_memory;
using testing_support::ScratchDir;

std::string long_jittery_drive(const std::string& duration) {
  return "seed: 9\nduration: " + duration +
         "\nworld:\n  gamepad: drive\n  vehicles:\n    - name: truck-1\n"
         "      link: {delay: 20ms, jitter: 5ms, loss: 0.01}\n"
         "expect:\n  thresholds:\n    latency_ms: [\"count > 0\"]\n    echo_delay_ms: [\"max < 100\"]\n"
         "    feedback_gap_ms: [\"max < 1000\"]\n";
}

TEST(ScenarioLongRun, TheSeriesOfHalfAnHourStayBounded) {
  RunOptions options;
  options.trace = false;
  const auto outcome = test::run_text(long_jittery_drive("30min"), options);
  const VehicleObservations& truck = outcome.run.observations.vehicles.at("truck-1");
  // 100 control ticks a second: 180 000 samples counted, at most plot_capacity kept for the plot.
  EXPECT_GT(truck.latency_ms.count(), 170'000u);
  EXPECT_LE(truck.latency_ms.points().size(), PlotSeries::plot_capacity);
  EXPECT_GT(truck.latency_ms.plot().stride(), 1u);
  EXPECT_LE(truck.control_gap_ms.points().size(), PlotSeries::plot_capacity);
  EXPECT_LE(truck.echo_delay_ms.points().size(), PlotSeries::plot_capacity);
  EXPECT_LE(truck.feedback_gap_ms.points().size(), PlotSeries::plot_capacity);
  EXPECT_LE(truck.ping_ms.points().size(), PlotSeries::plot_capacity);
  EXPECT_LE(truck.to_player_link.throughput_mbps.points().size(), PlotSeries::plot_capacity);
  EXPECT_LE(truck.to_streamer_link.queueing_delay_ms.points().size(), PlotSeries::plot_capacity);
  // The points still span the whole run.
  EXPECT_GT(truck.latency_ms.points().back().time, SimTime{29 * 60 * 1'000'000LL});
  for (const Verdict& verdict : outcome.verdicts) EXPECT_TRUE(verdict.passed) << verdict.title << ": " << verdict.actual;
}

// The trace goes to its file line by line: nothing of it is held, and the file is the trace
// the same run keeps in memory, byte for byte.
TEST(ScenarioLongRun, TheTraceIsWrittenToItsFileAsTheRunGoes) {
  ScratchDir scratch("ocp_long_run_trace");
  RunOptions to_file;
  to_file.trace_file = (scratch / "trace.jsonl").string();
  const auto streamed = test::run_text(long_jittery_drive("20s"), to_file);
  const auto in_memory = test::run_text(long_jittery_drive("20s"), RunOptions{});
  EXPECT_TRUE(streamed.run.trace_jsonl.empty());
  std::ifstream file(scratch / "trace.jsonl", std::ios::binary);
  std::stringstream text;
  text << file.rdbuf();
  ASSERT_GT(in_memory.run.trace_jsonl.size(), 100'000u);
  EXPECT_TRUE(text.str() == in_memory.run.trace_jsonl) << "the file differs from the trace";
  EXPECT_EQ(streamed.run.trace_digest, in_memory.run.trace_digest);
  EXPECT_EQ(streamed.run.trace_lines, in_memory.run.trace_lines);
}

TEST(ScenarioLongRun, AnUnwritableTraceFileIsAHarnessError) {
  RunOptions options;
  options.trace_file = "/nonexistent-folder/trace.jsonl";
  const Scenario scenario = parse_scenario(long_jittery_drive("1s"), "inline.yaml");
  EXPECT_THROW(run_scenario(scenario, options), HarnessError);
}

// ocp_scenario's peak memory: a run 8 times as long needs no more than a few MB more, with the
// trace (streamed to its file) and without it (the series). Before: +25 MB for 35 more
// minutes without a trace, and three copies of the trace in memory with it.
struct ToolMemoryCase {
  const char* what;
  const char* short_run;
  const char* long_run;
  bool trace;
};

class ScenarioToolMemory : public ::testing::TestWithParam<ToolMemoryCase> {};

TEST_P(ScenarioToolMemory, ALongRunNeedsNoMoreMemoryThanAShortOne) {
  if (!memory_is_measurable()) GTEST_SKIP() << "resident memory means nothing under AddressSanitizer";
  const ToolMemoryCase& run = GetParam();
  ScratchDir scratch("ocp_long_run_memory");
  const auto peak_kib = [&](const char* duration) {
    const std::string file = scratch.write(std::string("run-") + duration + ".yaml", long_jittery_drive(duration)).string();
    std::vector<std::string> argv{OCP_SCENARIO_PATH, "run", file, "--out", (scratch / "out").string()};
    if (!run.trace) argv.push_back("--no-trace");
    const auto measured = run_measuring_memory(argv);
    EXPECT_EQ(measured.exit_code, 0) << duration;
    return measured.peak_rss_kib;
  };
  const long short_kib = peak_kib(run.short_run);
  const long long_kib = peak_kib(run.long_run);
  EXPECT_LT(long_kib - short_kib, 8 * 1024) << run.what << ": " << short_kib << " KiB for " << run.short_run << ", "
                                             << long_kib << " KiB for " << run.long_run;
}

INSTANTIATE_TEST_SUITE_P(Runs, ScenarioToolMemory,
                         ::testing::Values(ToolMemoryCase{"series (no trace)", "5min", "40min", false},
                                           ToolMemoryCase{"trace streamed", "1min", "8min", true}),
                         [](const auto& info) { return info.param.trace ? std::string("Trace") : std::string("NoTrace"); });

}  // namespace
}  // namespace ocp::scenario
