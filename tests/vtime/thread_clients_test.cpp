// Multi-threaded client processes in virtual time (docs/virtual-time.md, "Which clients work"):
// the timed waits on an object that threads use to wait for one another (condition variables,
// semaphores, timed locks, futex words through syscall()) end exactly at their virtual
// deadline, or when another thread ends them; the two-thread vendor-shaped client and the Rust
// tokio client pass as in-process clients do, with the same verdicts every run (Node too). Real client
// processes: the runs have wall-clock (steady_clock) watchdogs from the Controller.
#include <gtest/gtest.h>

#include <cerrno>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "node_program.hpp"
#include "scratch_dir.hpp"
#include "virtual_run.hpp"

namespace ocp::vtime {
namespace {

std::vector<std::string> two_thread_client(bool condition_variable = false) {
  std::vector<std::string> argv{OCP_VTIME_TWO_THREAD_CLIENT, "127.0.0.1:{port}"};
  if (condition_variable) argv.insert(argv.begin() + 1, "--cv");
  return argv;
}

// The tokio client, when cargo was there to build it (scripts/setup --test installs it).
std::vector<std::string> tokio_client() { return {OCP_VTIME_TOKIO_CLIENT, "127.0.0.1:{port}"}; }
bool have_tokio_client() { return std::string(OCP_VTIME_TOKIO_CLIENT) != ""; }
#define SKIP_WITHOUT_TOKIO()                                                                                         \
  if (!have_tokio_client()) GTEST_SKIP() << "the Rust tokio client was not built: Debian's cargo and "              \
                                            "librust-tokio-dev are missing (scripts/setup --test installs them)"

TEST(VirtualTimeThreads, TimedWaitsEndAtTheirVirtualDeadlineOrWhenAnotherThreadEndsThem) {
  const testing_support::ScratchDir dir("vtime_timed_waits");
  const std::string log = (dir / "client.log").string();
  (void)run_client(world_yaml("3s", "  faults:\n    - {fault: InvalidMac, never: true}\n"), {OCP_VTIME_TIMED_WAITS_CLIENT}, {},
                   false, log);
  std::ifstream in(log);
  std::map<std::string, std::string> seen;
  for (std::string line; std::getline(in, line);) {
    const auto space = line.find(' ');
    seen[line.substr(0, space)] = space == std::string::npos ? "" : line.substr(space + 1);
  }
  auto expect = [](long result, long elapsed) {
    return "result=" + std::to_string(result) + " elapsed_us=" + std::to_string(elapsed);
  };
  const std::map<std::string, std::string> wanted{
      {"cond_timedwait_timeout", expect(ETIMEDOUT, 250'000)}, {"cv_wait_for_timeout", expect(ETIMEDOUT, 100'000)},
      {"cv_wait_for_notified", expect(0, 30'000)},            {"sem_timedwait_timeout", expect(ETIMEDOUT, 70'000)},
      {"sem_clockwait_posted", expect(0, 20'000)},            {"timedlock_acquired", expect(0, 40'000)},
      {"timedlock_timeout", expect(ETIMEDOUT, 50'000)},       {"futex_wait_timeout", expect(ETIMEDOUT, 60'000)},
      {"futex_bitset_timeout", expect(ETIMEDOUT, 80'000)},    {"futex_bitset_woken", expect(0, 10'000)},
      {"rwlock_timedwrlock_timeout", expect(ETIMEDOUT, 50'000)}, {"rwlock_timedrdlock_timeout", expect(ETIMEDOUT, 60'000)},
      {"rwlock_clockrdlock_acquired", expect(0, 40'000)},     {"rwlock_clockwrlock_acquired", expect(0, 30'000)},
  };
  for (const auto& [name, line] : wanted) EXPECT_EQ(seen[name], line) << name;
  EXPECT_TRUE(seen.contains("done")) << "the client did not finish its waits";
}


TEST(VirtualTimeThreads, TwoThreadClientWithSleepForEchoesEveryPair) { expect_echoes("two-thread client", two_thread_client()); }

TEST(VirtualTimeThreads, TwoThreadClientWithConditionVariableEchoesEveryPair) {
  expect_echoes("two-thread client (--cv)", two_thread_client(true));
}

TEST(VirtualTimeThreads, TokioClientEchoesEveryPair) {
  SKIP_WITHOUT_TOKIO();
  expect_echoes("tokio client", tokio_client());
}

// A multi-threaded client gives the same verdicts every run. Its threads may race within one
// virtual instant (the reader's answer and the timer's keep-alive), so its traces need not be
// identical: how often they are is printed (docs/virtual-time.md records it).
void expect_same_verdicts_ten_times(const std::string& name, const std::vector<std::string>& argv) {
  std::set<std::string> verdicts;
  std::map<std::string, int> traces;
  for (int run = 0; run < 10; ++run) {
    std::string expectations = echoing_client_expectations;   // scaled to 3 s
    expectations.replace(expectations.find("count > 900"), 11, "count > 270");
    const Ran ran = run_client(world_yaml("3s", expectations), argv, {}, true);
    std::ostringstream summary;
    for (const scenario::Verdict& verdict : ran.verdicts) summary << verdict.title << '=' << verdict.passed << ';';
    verdicts.insert(summary.str());
    ++traces[ran.run.result.trace_jsonl];
    expect_all_pass(ran);
  }
  EXPECT_EQ(verdicts.size(), 1u) << name << ": different verdicts in 10 runs";
  int most = 0;
  for (const auto& [trace, count] : traces) most = std::max(most, count);
  std::printf("%s: same verdicts %d/10 runs; %zu distinct traces, the most common in %d/10 runs\n", name.c_str(),
              verdicts.size() == 1 ? 10 : 0, traces.size(), most);
  if (traces.size() > 1) {
    std::printf("first difference:\n%s\n", first_difference(traces.begin()->first, std::next(traces.begin())->first).c_str());
  }
}

TEST(VirtualTimeThreads, TwoThreadClientGivesTheSameVerdictsTenTimes) {
  expect_same_verdicts_ten_times("two-thread client", two_thread_client());
}

// Node's one JavaScript thread beside libuv's and V8's threads.
TEST(VirtualTimeThreads, NodeExampleGivesTheSameVerdictsTenTimes) {
  OCP_SKIP_WITHOUT_NODE();
  const std::string script = std::string(OCP_EXAMPLES_DIR) + "/vehicle_client.js";
  expect_same_verdicts_ten_times("node example", {testing::node_program(), script, "127.0.0.1:{port}"});
}

TEST(VirtualTimeThreads, TokioClientGivesTheSameVerdictsTenTimes) {
  SKIP_WITHOUT_TOKIO();
  expect_same_verdicts_ten_times("tokio client", tokio_client());
}

}  // namespace
}  // namespace ocp::vtime
