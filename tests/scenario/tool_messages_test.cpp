// ocp_scenario as a user meets it (issue #20 items 8 and 9): the messages of a bad command line
// or file with exit code 2, the --repeat summary, and Ctrl-C — exit 130, "interrupted", reports
// marked. Runs the built tool; every wait is bounded, far above what a loaded machine needs.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "child_process.hpp"
#include "scenario_test_support.hpp"

namespace ocp::scenario {
namespace {

namespace fs = std::filesystem;

struct ToolRun {
  int exit_code = -1;
  std::string output;   // stdout and stderr
};

ToolRun run_tool_capturing(const std::string& arguments) {
  const ocp::test::CommandRun ran = ocp::test::run_command(std::string(OCP_SCENARIO_PATH) + " " + arguments);
  return ToolRun{ran.exit_code, ran.output};
}

// A scratch folder per test process.
class ToolTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("ocp_scenario_tool_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return (dir_ / name).string();
  }
  fs::path dir_;
};

const std::string library_dir = OCP_SCENARIO_LIBRARY_DIR;

struct BadCall {
  const char* what;
  std::string arguments;   // after `run`; FILE stands for a good scenario file
  std::string fragment;
};

void PrintTo(const BadCall& call, std::ostream* out) { *out << call.what; }

class ToolRefuses : public ::testing::TestWithParam<BadCall> {};

TEST_P(ToolRefuses, WithExitCode2AndAClearMessage) {
  const BadCall& call = GetParam();
  std::string arguments = call.arguments;
  if (const auto at = arguments.find("FILE"); at != std::string::npos) arguments.replace(at, 4, library_dir + "/gamepad_unplug.yaml");
  const ToolRun run = run_tool_capturing("run " + arguments + " --list");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find(call.fragment), std::string::npos) << run.output;
}

INSTANTIATE_TEST_SUITE_P(
    Table, ToolRefuses,
    ::testing::Values(
        BadCall{"missing file", "/nonexistent/foo.yaml", "error: /nonexistent/foo.yaml: cannot open the scenario file: No such file or directory"},
        BadCall{"negative seed", "FILE --seed -1", "--seed: expected a whole number in 0..18446744073709551615, got '-1'"},
        BadCall{"fractional seed", "FILE --seed 1.5", "got '1.5'"},
        BadCall{"seed past 2^64-1", "FILE --seed 18446744073709551616", "got '18446744073709551616'"},
        BadCall{"repeat 0", "FILE --repeat 0", "--repeat"}),
    [](const ::testing::TestParamInfo<BadCall>& info) {
      std::string name = info.param.what;
      for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
      return name;
    });

TEST_F(ToolTest, AMisIndentedLineSaysWhereAndWhatYamlExpected) {
  const std::string file = write("indent.yaml", "seed: 1\nduration: 1s\nworld:\n  vehicles:\n    - name: a\n     link: {delay: 2ms}\n"
                                                "expect: {invariants: [no_stale_pair_after_reconnect]}\n");
  const ToolRun run = run_tool_capturing("run " + file);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.output.find(file + ":6:6: YAML expected another list item"), std::string::npos) << run.output;
}

TEST_F(ToolTest, RepeatEndsWithOneSummaryPerExpectation) {
  const ToolRun run = run_tool_capturing("run " + library_dir + "/gamepad_unplug.yaml --repeat 3 --no-trace --out " + (dir_ / "out").string());
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("gamepad_unplug.yaml: 3 seeds\n"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find(": passed 3 of 3 seeds\n"), std::string::npos) << run.output;
}

// The tool in a child process with its output on a pipe, to signal it mid-run.
using Child = ocp::test::ChildProcess;

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Real time: the tool waits for an external vehicle that never comes; Ctrl-C ends the run.
TEST_F(ToolTest, CtrlCInRealTimeExits130WithReportsMarkedInterrupted) {
  const std::string file = write("waits.yaml", R"(duration: 60s
world:
  vehicles: [{name: truck-1, in_process_client: false}]
expect:
  faults:
    - {fault: VehicleNoResponse, cleared: {after: 0s, within: 50s}}
)");
  Child tool({OCP_SCENARIO_PATH, "run", file, "--realtime", "--tcp-port", "0", "--out", (dir_ / "out").string(), "--junit",
              (dir_ / "junit.xml").string()});
  ASSERT_TRUE(tool.wait_for("waiting for a vehicle client", std::chrono::seconds(30))) << tool.output();
  tool.signal(SIGINT);
  ASSERT_EQ(tool.wait_exit(std::chrono::seconds(30)), 130) << tool.output();
  EXPECT_NE(tool.output().find("\ninterrupted: "), std::string::npos) << tool.output();
  EXPECT_NE(tool.output().find("not judged: the run was interrupted at "), std::string::npos) << tool.output();
  const std::string summary = read_text(dir_ / "out" / "waits" / "summary.json");
  EXPECT_NE(summary.find("\"interrupted\": true"), std::string::npos) << summary;
  EXPECT_NE(read_text(dir_ / "out" / "waits" / "report.html").find("○ interrupted"), std::string::npos);
  EXPECT_NE(read_text(dir_ / "junit.xml").find("<testsuites interrupted=\"true\">"), std::string::npos);
}

// Virtual time with --repeat: SIGTERM during the second seed or later keeps the seeds finished
// so far, summarised. SIGHUP (a closed SSH session, a CI runner's cancel) does the same: exit
// 130, the JUnit written, no line cut short.
TEST_F(ToolTest, SigtermOrSighupDuringRepeatKeepsTheFinishedSeeds) {
  const std::string file = write("long.yaml", R"(duration: 5min
world: {gamepad: drive, vehicles: [{name: truck-1}]}
expect:
  thresholds: {latency_ms: ["count > 0"]}
)");
  for (const int signal_number : {SIGTERM, SIGHUP}) {
    SCOPED_TRACE(signal_number == SIGTERM ? "SIGTERM" : "SIGHUP");
    Child tool({OCP_SCENARIO_PATH, "run", file, "--repeat", "1000", "--no-trace", "--out", (dir_ / "out").string(),
                "--junit", (dir_ / "junit.xml").string()});
    ASSERT_TRUE(tool.wait_for("✓ " + file, std::chrono::seconds(120))) << tool.output();
    tool.signal(signal_number);
    ASSERT_EQ(tool.wait_exit(std::chrono::seconds(120)), 130) << tool.output();
    EXPECT_NE(tool.output().find("long.yaml: "), std::string::npos) << tool.output();
    EXPECT_NE(tool.output().find("\n  ✓ latency_ms: count > 0: passed "), std::string::npos) << tool.output();
    EXPECT_NE(tool.output().find("\ninterrupted: "), std::string::npos) << tool.output();
    EXPECT_EQ(tool.output().back(), '\n') << tool.output();
    EXPECT_NE(read_text(dir_ / "junit.xml").find("<testsuites interrupted=\"true\">"), std::string::npos);
  }
}

// `ocp_scenario run … | head -c1`: a closed stdout loses no report. Every file still runs and
// writes its summary, and the tool exits with its verdict (not 141, SIGPIPE).
TEST_F(ToolTest, AClosedStdoutLosesNoReport) {
  std::vector<std::string> files;
  for (int i = 0; i < 4; ++i) {
    files.push_back(write("short" + std::to_string(i) + ".yaml", R"(duration: 2s
world: {gamepad: drive, vehicles: [{name: truck-1}]}
expect:
  thresholds: {latency_ms: ["count > 0"]}
)"));
  }
  std::string command = std::string(OCP_SCENARIO_PATH) + " run --no-trace --out " + (dir_ / "out").string();
  for (const std::string& file : files) command += " " + file;
  command += " | head -c1 >/dev/null; exit ${PIPESTATUS[0]}";
  const int status = std::system(("bash -c '" + command + "'").c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  for (int i = 0; i < 4; ++i) {
    const std::string summary = read_text(dir_ / "out" / ("short" + std::to_string(i)) / "summary.json");
    EXPECT_NE(summary.find("\"interrupted\": false"), std::string::npos) << i << summary;
  }
}

}  // namespace
}  // namespace ocp::scenario
