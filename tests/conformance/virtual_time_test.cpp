// `ocp_conformance … --time virtual -- CMD` (docs/virtual-time.md): the launched client runs
// under the shim on the suite's own clock. Every case's timing is exact, so the good clients get
// OK on every case with no allowance for the machine's load; a client that cannot live in virtual
// time is refused (exit 2, with the reason and the way out) and never hangs the run. The broken
// clients' verdicts in virtual time are the coverage rows of suite_test.cpp (InVirtualTime), and
// a client that crashes in a case is named there in both times.
#include <gtest/gtest.h>

#include <chrono>
#include <map>
#include <set>
#include <string>

#include "suite_run.hpp"

namespace {

using namespace ocp::conformance_test;

// The Python vehicle example sends no safety report: SPEC §10's cases are not judged.
const std::map<std::string, std::string> no_safety_report{{"vehicle/10/1", "INFORMATIONAL"},
                                                          {"vehicle/10/2", "INFORMATIONAL"},
                                                          {"vehicle/10/3", "INFORMATIONAL"},
                                                          {"vehicle/10/4", "INFORMATIONAL"}};
const std::map<std::string, std::string> operator_info{{"operator/4.2/6", "INFORMATIONAL"},
                                                       {"operator/4.4/1", "INFORMATIONAL"}};

// No wall-clock allowance here (the real-time run allows vehicle/3.3/2 a NON-STRICT on a busy
// machine): in virtual time the reference client answers at the instant it reads.
TEST(ConformanceVirtualTime, ReferenceClientPassesEveryCaseExactly) {
  const SuiteRun r = run_suite("virtual_reference", "-j 2 --time virtual", reference + " 127.0.0.1:{port} --no-status");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("in virtual time"), std::string::npos) << r.output;
  EXPECT_GE(expect_every_case_ok(r), 19u);
}

// An example pair (vehicle and operator client) passes both suites in virtual time: every case OK
// but the ones an example cannot pass (no safety report; the operator suite's INFO cases).
void expect_examples_pass_both_suites(const std::string& name, const std::string& vehicle_client,
                                      const std::string& operator_client) {
  const SuiteRun vehicle = run_suite(name + "_vehicle", "-j 2 --time virtual", vehicle_client);
  ASSERT_EQ(vehicle.exit_code, 0) << vehicle.output;
  EXPECT_GE(expect_every_case_ok(vehicle, no_safety_report), 19u);
  const SuiteRun operator_side = run_suite(name + "_operator", "-j 2 --time virtual", operator_client, "operator");
  ASSERT_EQ(operator_side.exit_code, 0) << operator_side.output;
  EXPECT_GE(expect_every_case_ok(operator_side, operator_info), 19u);
}

TEST(ConformanceVirtualTime, PythonExamplesPassBothSuites) {
  expect_examples_pass_both_suites("virtual_example", example_client("vehicle_client.py"), example_client("operator_client.py"));
}

// A whole-suite run of a broken client in virtual time fails exactly its own cases, as in real
// time (BrokenClientExactly in suite_test.cpp).
TEST(ConformanceVirtualTime, ABrokenClientFailsExactlyItsOwnCases) {
  const SuiteRun r = run_suite("virtual_naive_recv", "-j 2 --restart-per-case --time virtual", python_client("naive-recv"));
  ASSERT_TRUE(r.index.IsObject()) << r.output;
  std::set<std::string> failed;
  for (const auto& c : r.index["cases"].GetArray()) {
    if (std::string(c["verdict"].GetString()) == "FAILED") failed.insert(c["id"].GetString());
  }
  EXPECT_EQ(failed, (std::set<std::string>{"vehicle/2/3", "vehicle/2/4", "vehicle/3.2/4"})) << r.output;
  EXPECT_EQ(r.exit_code, 1) << r.output;
}

// The other client kinds of docs/virtual-time.md pass the vehicle suite in virtual time too:
// Node (libuv: epoll, timerfd, every descriptor closed through syscall(SYS_close)), a two-thread
// C++ client (a reader thread, a sleep_for or condition-variable timer thread) and a tokio
// multi-thread runtime (futex parking through syscall()). None sends a safety report.

TEST(ConformanceVirtualTime, NodeExamplesPassBothSuites) {
  OCP_SKIP_WITHOUT_NODE();
  expect_examples_pass_both_suites("virtual_node", node_example_client("vehicle_client.js"), node_example_client("operator_client.js"));
}

#ifdef OCP_VTIME_TWO_THREAD_CLIENT
// The test clients are minimal: they close on a frame above 16 KiB (vehicle/2/5, a robustness
// check: NON-STRICT), and tokio's keep-alive task may answer a frame before its reader does
// (vehicle/3.3/2: "answers on its own schedule", NON-STRICT).
std::map<std::string, std::string> minimal_client_verdicts(bool own_schedule) {
  std::map<std::string, std::string> allowed = no_safety_report;
  allowed["vehicle/2/5"] = "NON-STRICT";
  if (own_schedule) allowed["vehicle/3.3/2"] = "NON-STRICT";
  return allowed;
}

TEST(ConformanceVirtualTime, TwoThreadClientsPassTheVehicleSuite) {
  for (const std::string timer : {"", "--cv "}) {
    const SuiteRun r = run_suite("virtual_two_thread", "-j 2 --time virtual",
                                 std::string(OCP_VTIME_TWO_THREAD_CLIENT) + " " + timer + "127.0.0.1:{port}");
    ASSERT_EQ(r.exit_code, 0) << timer << r.output;
    EXPECT_GE(expect_every_case_ok(r, minimal_client_verdicts(false)), 19u) << timer;
  }
}

TEST(ConformanceVirtualTime, TokioClientPassesTheVehicleSuite) {
  if (std::string(OCP_VTIME_TOKIO_CLIENT).empty())
    GTEST_SKIP() << "the Rust tokio client was not built: Debian's cargo and crates are missing (scripts/setup --test)";
  const SuiteRun r = run_suite("virtual_tokio", "-j 2 --time virtual", std::string(OCP_VTIME_TOKIO_CLIENT) + " 127.0.0.1:{port}");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_GE(expect_every_case_ok(r, minimal_client_verdicts(true)), 19u);
}
#endif

#ifdef OCP_VTIME_STATIC_CLIENT
TEST(ConformanceVirtualTime, AStaticBinaryIsRefusedWithTheWayOut) {
  const auto start = std::chrono::steady_clock::now();
  const SuiteRun r = run_suite("virtual_static", "--time virtual --cases vehicle/2/1", OCP_VTIME_STATIC_CLIENT);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("cannot run in virtual time"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("use --time real"), std::string::npos) << r.output;
  EXPECT_LT(seconds_since(start), 60.0) << r.output;   // the 2 s handshake timeout, not a hang
}
#endif

// The connect timeout is virtual: a client asleep for 600 s ends the run after 5 virtual
// seconds, in far less wall time.
TEST(ConformanceVirtualTime, AClientThatNeverConnectsStopsTheRunAfterTheVirtualConnectTimeout) {
  const auto start = std::chrono::steady_clock::now();
  const SuiteRun r = run_suite("virtual_never_connects", "--time virtual --connect-timeout-s 5", "sleep 600");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("within 5.0 s of its launch"), std::string::npos) << r.output;
  EXPECT_LT(seconds_since(start), 60.0) << r.output;
}

// A client that never waits cannot let virtual time pass: a harness error naming it, not a hang.
// At nice 19, so that its 3 s of CPU never starve the real-time tests ctest runs beside it.
TEST(ConformanceVirtualTime, ABusyLoopIsAHarnessErrorNotAHang) {
  const std::string spins =
      "nice -n 19 python3 -c \"import os, socket; s = socket.create_connection(('127.0.0.1', int(os.environ['OCP_PORT'])))\n"
      "while True: pass\"";
  const auto start = std::chrono::steady_clock::now();
  const SuiteRun r = run_suite("virtual_busy", "--time virtual --cases vehicle/3.3/1", spins);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("without ever waiting"), std::string::npos) << r.output;
  EXPECT_LT(seconds_since(start), 90.0) << r.output;
}

// With -- CMD and no --time the suite runs in virtual time, and Nagle's delay on a split write
// (the prefix and the payload in two writes, no TCP_NODELAY) is caught there as in real time:
// vehicle/3.3/2 NON-STRICT, the cause named (docs/virtual-time.md, "Nagle's algorithm").
TEST(ConformanceVirtualTime, TheDefaultWithALaunchedClientIsVirtualAndCatchesNaglesDelay) {
  const std::string dir = fresh_dir("virtual_default_split_write");
  const auto start = std::chrono::steady_clock::now();
  const int code = run(harness + " vehicle --cases vehicle/3.3/2 --connect-timeout-s 60 --out " + dir + " -- " +
                           python_client("split-write"),
                       dir + "/out.txt");
  const std::string output = read_file(dir + "/out.txt");
  EXPECT_EQ(code, 0) << output;   // a SHOULD case: NON-STRICT is not a failure
  EXPECT_NE(output.find("in virtual time"), std::string::npos) << output;
  EXPECT_NE(output.find("NON-STRICT  ] vehicle/3.3/2"), std::string::npos) << output;
  EXPECT_NE(output.find("Cause found: Nagle's delay on a split write"), std::string::npos) << output;
  EXPECT_LT(seconds_since(start), 60.0) << output;
}

TEST(ConformanceVirtualTime, NeedsALaunchedClient) {
  const std::string dir = fresh_dir("virtual_no_command");
  EXPECT_EQ(run(harness + " vehicle --time virtual", dir + "/out.txt"), 2);
  EXPECT_NE(read_file(dir + "/out.txt").find("--time virtual launches the client"), std::string::npos)
      << read_file(dir + "/out.txt");
  EXPECT_EQ(run(harness + " vehicle --time warp -- true", dir + "/warp.txt"), 2);
}

}  // namespace
