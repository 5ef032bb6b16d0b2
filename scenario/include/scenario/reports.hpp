#pragma once
// What a run leaves behind: summary.json, report.html (self-contained: inline SVG, the
// summary embedded as <script type="application/json" id="summary">), JUnit XML, and the
// k6-style console lines.
#include <string>
#include <vector>

#include "scenario/model.hpp"
#include "scenario/runner.hpp"
#include "scenario/verdicts.hpp"

namespace ocp::scenario {

struct RunReport {
  const Scenario* scenario = nullptr;
  const RunResult* run = nullptr;
  std::vector<Verdict> verdicts;
  std::string reproduce;   // the command that repeats this run
};

std::string summary_json(const RunReport& report);
// `summary` is summary_json(report): embedded verbatim (only "</" escaped as "<\/").
std::string report_html(const RunReport& report, const std::string& summary);
// One testsuite per run, one testcase per expectation; a verdict not judged (Ctrl-C) is
// <skipped>. `interrupted`: the tool was stopped, so runs are missing (<testsuites interrupted="true">).
std::string junit_xml(const std::vector<RunReport>& reports, bool interrupted = false);
// After --repeat: one line per expectation of each file, "passed k of n seeds", with the
// seeds that failed (runs cut short by Ctrl-C are left out: they were not finished).
std::string repeat_summary(const std::vector<RunReport>& reports);
// "  ✓ title … actual" lines, as k6 prints thresholds.
std::string console_verdicts(const RunReport& report);

}  // namespace ocp::scenario
