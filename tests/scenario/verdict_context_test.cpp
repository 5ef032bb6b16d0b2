// Verdicts that say what the fault was doing before the anchor (issue #20 item 9), and what a
// run cut short by Ctrl-C can and cannot judge (item 8). Observations are made by hand: the
// rule is about the judging, not about the World.
#include "scenario/reports.hpp"
#include "scenario_test_support.hpp"

namespace ocp::scenario {
namespace {

constexpr Micros secs(double seconds) { return Micros{static_cast<std::int64_t>(seconds * 1e6)}; }

// One expectation on HighLatency around the event `ramp_up` at 10 s.
Scenario edge_scenario(const std::string& edge) {
  return parse_scenario(R"(duration: 20s
world: {vehicles: [{name: truck-1}]}
timeline:
  - {at: 10s, name: ramp_up, impair: {delay: 300ms}}
expect:
  faults:
    - {fault: HighLatency, )" + edge + R"(: {after: ramp_up, within: 2s}}
)", "edge.yaml");
}

struct Before {
  const char* what;
  const char* edge;                 // raised or cleared
  std::vector<Interval> intervals;  // HighLatency on truck-1
  bool passed;
  const char* actual;               // a fragment of the verdict's actual
};

void PrintTo(const Before& before, std::ostream* out) { *out << before.what; }

Interval open_from(double start) { return {secs(start), std::nullopt}; }
Interval closed_between(double start, double end) { return {secs(start), secs(end)}; }

// Five raises between 6 s and 10 s, the last one cleared just before the event.
std::vector<Interval> flapping(std::vector<Interval> after) {
  std::vector<Interval> list = {closed_between(6, 6.5), closed_between(7, 7.5), closed_between(8, 8.5), closed_between(9, 9.5), closed_between(9.8, 9.9)};
  list.insert(list.end(), after.begin(), after.end());
  return list;
}

class FaultBeforeTheAnchor : public ::testing::TestWithParam<Before> {};

TEST_P(FaultBeforeTheAnchor, IsReportedAsSuch) {
  const Before& before = GetParam();
  const Scenario scenario = edge_scenario(before.edge);
  RunResult run;
  run.duration = run.ran = scenario.duration;
  run.observations.faults[{"truck-1", FaultId::HighLatency}] = before.intervals;
  const std::vector<Verdict> verdicts = evaluate(scenario, run);
  ASSERT_EQ(verdicts.size(), 1u);
  EXPECT_EQ(verdicts[0].passed, before.passed) << verdicts[0].actual;
  EXPECT_NE(verdicts[0].actual.find(before.actual), std::string::npos) << verdicts[0].actual;
}

INSTANTIATE_TEST_SUITE_P(
    Table, FaultBeforeTheAnchor,
    ::testing::Values(
        Before{"quiet before, raised after", "raised", {open_from(11.5)}, true, "raised 1.5s after ramp_up (at 11.5s)"},
        Before{"raised and cleared once long before", "raised", {closed_between(2, 3), open_from(11)}, true, "raised 1s after ramp_up"},
        Before{"already active at the event", "raised", {open_from(4)},
               false, "already active at ramp_up (raised at 4s); never raised after ramp_up"},
        Before{"already active, raised again later", "raised", {closed_between(4, 10.5), open_from(11)},
               false, "already active at ramp_up (raised at 4s); next raised 1s after ramp_up (at 11s)"},
        Before{"flapping, raised right at the event", "raised", flapping({open_from(10)}),
               false, "already flapping before ramp_up (raised 5 times in the 5s before it); next raised 0ms after ramp_up"},
        Before{"three raises are not flapping", "raised", {closed_between(7, 7.5), closed_between(8, 8.5), closed_between(9, 9.5), open_from(11)},
               true, "raised 1s after ramp_up"},
        Before{"active at the event, cleared after: the normal clear", "cleared", {closed_between(4, 11)}, true, "cleared 1s after ramp_up"},
        Before{"flapping, cleared after", "cleared", flapping({closed_between(10.1, 10.2)}),
               false, "already flapping before ramp_up (raised 5 times in the 5s before it); next cleared 200ms after ramp_up"}),
    [](const ::testing::TestParamInfo<Before>& info) {
      std::string name = info.param.what;
      for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
      return name;
    });

// --- a run cut short at 5 s of 20 s ---------------------------------------------------------

struct Cut {
  const char* what;
  std::string expectation;   // one entry of expect: (YAML)
  bool passed, interrupted;
  const char* actual;
};

void PrintTo(const Cut& cut, std::ostream* out) { *out << cut.what; }

class InterruptedRun : public ::testing::TestWithParam<Cut> {};

TEST_P(InterruptedRun, JudgesOnlyWhatItSaw) {
  const Cut& cut = GetParam();
  const Scenario scenario = parse_scenario(R"(duration: 20s
world: {vehicles: [{name: truck-1}]}
timeline:
  - {at: 2s, name: early, gamepad: unplug}
  - {at: 4s, name: late, gamepad: replug}
expect:
)" + cut.expectation, "cut.yaml");
  RunResult run;
  run.duration = scenario.duration;
  run.ran = secs(5);
  run.interrupted = true;
  run.observations.faults[{"truck-1", FaultId::InputLost}] = {closed_between(2.01, 4.01)};
  run.observations.vehicles["truck-1"].latency_ms.add(secs(1), 40.0);
  run.observations.vehicles["truck-1"].latency_ms.add(secs(3), 60.0);
  const std::vector<Verdict> verdicts = evaluate(scenario, run);
  ASSERT_EQ(verdicts.size(), 1u);
  EXPECT_EQ(verdicts[0].passed, cut.passed) << verdicts[0].actual;
  EXPECT_EQ(verdicts[0].interrupted, cut.interrupted) << verdicts[0].actual;
  EXPECT_NE(verdicts[0].actual.find(cut.actual), std::string::npos) << verdicts[0].actual;
}

INSTANTIATE_TEST_SUITE_P(
    Table, InterruptedRun,
    ::testing::Values(
        Cut{"an edge seen before the cut", "  faults: [{fault: InputLost, raised: {after: early, within: 50ms}}]\n", true, false,
            "raised 10ms after early"},
        Cut{"an edge seen late: failed for good", "  faults: [{fault: InputLost, raised: {after: early, within: 5ms}}]\n", false, false,
            "raised 10ms after early"},
        Cut{"a window that closed before the cut", "  faults: [{fault: CameraLost, raised: {after: early, within: 1s}}]\n", false, false,
            "never raised after early"},
        Cut{"a window still open at the cut", "  faults: [{fault: CameraLost, raised: {after: late, within: 5s}}]\n", false, true,
            "not judged: the run was interrupted at 5s of 20s (so far: never raised after late)"},
        Cut{"never, nothing seen yet", "  faults: [{fault: InvalidMac, never: true}]\n", false, true, "not judged"},
        Cut{"never, but raised: failed for good", "  faults: [{fault: InputLost, never: true}]\n", false, false,
            "raised 1 time(s)"},
        Cut{"a state before the cut", "  faults: [{fault: InputLost, at: 3s, active_on: [truck-1]}]\n", true, false,
            "truck-1=active"},
        Cut{"a state after the cut", "  faults: [{fault: InputLost, at: 10s, inactive_on: [truck-1]}]\n", false, true,
            "not judged"},
        Cut{"a threshold needs the whole run", "  thresholds: {latency_ms: [\"max < 100\"]}\n", false, true,
            "(so far: max = 60)"},
        Cut{"an invariant that saw nothing wrong yet", "  invariants: [no_stale_pair_after_reconnect]\n", false, true,
            "not judged"}),
    [](const ::testing::TestParamInfo<Cut>& info) {
      std::string name = info.param.what;
      for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
      return name;
    });

// A virtual-time run told to stop stops there, and every report says so.
TEST(InterruptedVirtualRun, StopsAndMarksItsReports) {
  test::Outcome outcome{parse_scenario(test::one_vehicle(R"(expect:
  thresholds:
    latency_ms: ["count > 0"]
)", "60s"), "stopped.yaml"), {}, {}};
  RunOptions options;
  int polls = 0;
  options.interrupted = [&] { return ++polls > 20; };   // polled every 100 ms of virtual time
  outcome.run = run_scenario(outcome.scenario, options);
  EXPECT_TRUE(outcome.run.interrupted);
  EXPECT_EQ(outcome.run.ran, secs(2));
  outcome.verdicts = evaluate(outcome.scenario, outcome.run);
  ASSERT_EQ(outcome.verdicts.size(), 1u);
  EXPECT_TRUE(outcome.verdicts[0].interrupted);
  const RunReport report{&outcome.scenario, &outcome.run, outcome.verdicts, "ocp_scenario run stopped.yaml"};
  const std::string summary = summary_json(report);
  EXPECT_NE(summary.find("\"interrupted\": true"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"passed\": false"), std::string::npos);
  EXPECT_NE(report_html(report, summary).find("○ interrupted"), std::string::npos);
  const std::string junit = junit_xml({report}, true);
  EXPECT_NE(junit.find("<testsuites interrupted=\"true\">"), std::string::npos) << junit;
  EXPECT_NE(junit.find("<skipped message=\"not judged"), std::string::npos) << junit;
  EXPECT_NE(console_verdicts(report).find("  ○ latency_ms: count > 0"), std::string::npos);
}

// Slices of 100 ms change nothing: a run that is not interrupted is the run it always was.
TEST(InterruptedVirtualRun, NeverInterruptedIsTheSameRun) {
  const std::string text = test::one_vehicle("expect:\n  thresholds:\n    latency_ms: [\"count > 0\"]\n", "3s");
  RunOptions polled;
  polled.interrupted = [] { return false; };
  const auto plain = test::run_text(text);
  const auto sliced = test::run_text(text, polled);
  EXPECT_FALSE(sliced.run.interrupted);
  EXPECT_EQ(sliced.run.ran, secs(3));
  EXPECT_EQ(plain.run.trace_digest, sliced.run.trace_digest);
}

// --repeat: one line per expectation, passed k of n, the failing seeds named.
TEST(RepeatSummary, PassedKOfNSeeds) {
  const Scenario scenario = parse_scenario(test::one_vehicle(
      "expect:\n  thresholds:\n    latency_ms: [\"count > 0\", \"max < 50\"]\n"), "repeat.yaml");
  std::vector<RunResult> runs(4);
  std::vector<RunReport> reports;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    runs[i].seed = 100 + i;
    runs[i].interrupted = i == 3;   // cut short: not finished, not counted
    std::vector<Verdict> verdicts(2);
    verdicts[0].passed = true;
    verdicts[1].passed = i == 0;
    reports.push_back({&scenario, &runs[i], verdicts, ""});
  }
  const std::string text = repeat_summary(reports);
  EXPECT_NE(text.find("repeat.yaml: 3 seeds\n"), std::string::npos) << text;
  EXPECT_NE(text.find("  ✓ latency_ms: count > 0: passed 3 of 3 seeds\n"), std::string::npos) << text;
  EXPECT_NE(text.find("  ✗ latency_ms: max < 50: passed 1 of 3 seeds; failed with seeds 101, 102\n"), std::string::npos) << text;
}

}  // namespace
}  // namespace ocp::scenario
