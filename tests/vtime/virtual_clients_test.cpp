// External client processes in virtual time (vtime/, docs/virtual-time.md): the reference
// client and the Python example live on the World's clock, a run is a pure function of its
// seed, a timing bug is caught to the microsecond, and a client that cannot live in virtual
// time is refused with the reason. Every run has a wall-clock watchdog (the Controller's), so
// a broken shim fails a test instead of hanging it (std::chrono::steady_clock bounds below).
#include <gtest/gtest.h>

#include <chrono>
#include <set>
#include <string>
#include <vector>

#include "node_program.hpp"
#include "virtual_run.hpp"

namespace ocp::vtime {
namespace {

std::vector<std::string> reference_client() { return {OCP_VEHICLE_CLIENT_PATH, "--no-status", "127.0.0.1:{port}"}; }
std::vector<std::string> python_example() {
  return {OCP_PYTHON3_PATH, std::string(OCP_EXAMPLES_DIR) + "/vehicle_client.py", "127.0.0.1:{port}"};
}

TEST(VirtualTimeClients, ReferenceClientEchoesEveryPairOnTheWorldsClock) {
  const Ran ran = expect_echoes("reference client", reference_client());
  ASSERT_EQ(ran.run.clients.size(), 1u);
  EXPECT_TRUE(ran.run.clients.front().process->running()) << "the client must live through the world";
}

std::vector<std::string> node_example() {
  return {testing::node_program(), std::string(OCP_EXAMPLES_DIR) + "/vehicle_client.js", "127.0.0.1:{port}"};
}

TEST(VirtualTimeClients, NodeExampleEchoesEveryPairOnTheWorldsClock) {
  OCP_SKIP_WITHOUT_NODE();
  expect_echoes("node example", node_example());
}

TEST(VirtualTimeClients, PythonExampleEchoesEveryPairOnTheWorldsClock) { expect_echoes("python example", python_example()); }

// The same seed gives the same trace, byte for byte, every time: the client's echoes land at
// the same virtual instants whatever the machine's load.
TEST(VirtualTimeClients, SameSeedSameTraceTenTimes) {
  for (const auto& [name, argv] : {std::pair{"reference client", reference_client()}, std::pair{"python example", python_example()}}) {
    std::set<std::string> traces;
    std::size_t lines = 0;
    for (int run = 0; run < 10; ++run) {
      const Ran ran = run_client(world_yaml("3s", echoing_client_expectations), argv, {}, true);
      traces.insert(ran.run.result.trace_jsonl);
      lines = ran.run.result.trace_lines;
    }
    EXPECT_EQ(traces.size(), 1u) << name << ": " << traces.size() << " different traces in 10 runs; first difference:\n"
                                 << first_difference(*traces.begin(), *traces.rbegin());
    EXPECT_GT(lines, 1000u) << name;
  }
}

// A broken client fails in virtual time as in real time: a wrong MAC raises InvalidMac.
TEST(VirtualTimeClients, BrokenReferenceClientFails) {
  std::vector<std::string> argv = reference_client();
  argv.insert(argv.begin() + 1, "--misbehave-corrupt-mac");
  const Ran ran = run_client(world_yaml("3s", "  faults:\n    - {fault: InvalidMac, never: true}\n"), argv);
  ASSERT_EQ(ran.verdicts.size(), 1u);
  EXPECT_FALSE(ran.verdicts.front().passed) << "InvalidMac must be raised against a client that corrupts the MAC";
}

// The close and open times of the vehicle connection, from the trace.
std::vector<std::int64_t> connection_times(const std::string& trace, const std::string& change) {
  std::vector<std::int64_t> times;
  std::size_t at = 0;
  while ((at = trace.find("\"change\":\"" + change + "\"", at)) != std::string::npos) {
    const std::size_t line = trace.rfind('\n', at) + 1;
    times.push_back(std::stoll(trace.substr(line + 8)));   // {"t_us":N
    ++at;
  }
  return times;
}

std::string lines_with(const std::string& trace, const std::string& text) {
  std::string out;
  std::size_t at = 0;
  while ((at = trace.find(text, at)) != std::string::npos) {
    const std::size_t begin = trace.rfind('\n', at) + 1;
    const std::size_t end = trace.find('\n', at);
    out += trace.substr(begin, end - begin) + "\n";
    at = end;
  }
  return out;
}

// A keep-alive every 2 001 ms is 1 ms too slow: the Streamer closes the connection after
// exactly 2 000 ms without a byte, every run. One every 1 999 ms keeps it.
TEST(VirtualTimeClients, KeepAliveOneMillisecondTooSlowIsClosedAtExactlyTwoSeconds) {
  const std::string script = std::string(OCP_VTIME_TEST_CLIENTS) + "/keepalive_client.py";
  const Ran slow = run_client(world_yaml("3s", "  faults:\n    - {fault: InvalidMac, never: true, from: 5s}\n"),
                              {OCP_PYTHON3_PATH, script, "{port}", "2.001"}, {}, true);
  const std::vector<std::int64_t> opened = connection_times(slow.run.result.trace_jsonl, "opened");
  const std::vector<std::int64_t> closed = connection_times(slow.run.result.trace_jsonl, "closed");
  ASSERT_FALSE(opened.empty());
  ASSERT_FALSE(closed.empty()) << "a client silent for 2 001 ms must be closed";
  EXPECT_EQ(closed.front() - opened.front(), 2'000'000) << "closed after exactly 2 000 ms of silence";
  EXPECT_NE(slow.run.result.trace_jsonl.find("peer.read_timeout"), std::string::npos);

  const Ran fast = run_client(world_yaml("3s", "  faults:\n    - {fault: InvalidMac, never: true, from: 5s}\n"),
                              {OCP_PYTHON3_PATH, script, "{port}", "1.999"}, {}, true);
  EXPECT_TRUE(connection_times(fast.run.result.trace_jsonl, "closed").empty())
      << "1 999 ms is within the read timeout; connection events:\n" << lines_with(fast.run.result.trace_jsonl, "\"connection\"");
}

// A static binary never loads the shim: refused within the handshake timeout, with the way out.
TEST(VirtualTimeClients, StaticBinaryIsRefusedWithTheReason) {
  const auto start = std::chrono::steady_clock::now();
  try {
    (void)run_client(world_yaml("3s", echoing_client_expectations), {OCP_VTIME_STATIC_CLIENT});
    FAIL() << "a static binary cannot run in virtual time";
  } catch (const VirtualTimeError& error) {
    EXPECT_NE(std::string(error.what()).find("cannot run in virtual time"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("use --time real"), std::string::npos) << error.what();
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(30));
}

// A loop of zero-timeout polls lets virtual time pass (1 µs every 64 fruitless polls, as Shadow
// models unblocked system calls): a client that polls until its clock moves (here for 2 ms,
// before it runs the Python example) gets there, and is not called a busy loop. Without the
// tick it spins at one instant for ever; Python's float time arithmetic does that by itself at
// some instants ("wait 0 s", "not due yet").
TEST(VirtualTimeClients, ZeroTimeoutPollsLetVirtualTimePass) {
  const std::string program = "import runpy, select, sys, time\n"
                              "start = time.monotonic()\n"
                              "while time.monotonic() - start < 0.002: select.select([], [], [], 0)\n"
                              "sys.argv = sys.argv[1:]\n"
                              "runpy.run_path(sys.argv[0], run_name='__main__')\n";
  expect_echoes("zero-timeout polls, then the python example",
                {OCP_PYTHON3_PATH, "-c", program, std::string(OCP_EXAMPLES_DIR) + "/vehicle_client.py", "127.0.0.1:{port}"});
}

// A client that never waits is found out after a bounded amount of CPU.
TEST(VirtualTimeClients, BusyLoopIsFoundOut) {
  ControllerOptions controller;
  controller.busy_cpu = std::chrono::milliseconds(300);
  try {
    (void)run_client(world_yaml("3s", echoing_client_expectations), {OCP_PYTHON3_PATH, "-c", "while True: pass"}, controller);
    FAIL() << "a busy loop must end the run";
  } catch (const VirtualTimeError& error) {
    EXPECT_NE(std::string(error.what()).find("without ever waiting"), std::string::npos) << error.what();
  }
}

// A busy client that a loaded machine starves of CPU never burns busy_cpu: it is found out by
// the wall time it ran without a quiescent instant (here with a CPU budget of an hour).
TEST(VirtualTimeClients, BusyLoopStarvedOfCpuIsFoundOutByWallTime) {
  ControllerOptions controller;
  controller.busy_cpu = std::chrono::hours(1);
  controller.busy_wall = std::chrono::milliseconds(1500);
  const auto start = std::chrono::steady_clock::now();
  try {
    (void)run_client(world_yaml("3s", echoing_client_expectations), {OCP_PYTHON3_PATH, "-c", "while True: pass"}, controller);
    FAIL() << "a busy loop must end the run";
  } catch (const VirtualTimeError& error) {
    EXPECT_NE(std::string(error.what()).find("s of wall time without ever waiting"), std::string::npos) << error.what();
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(60));
}

}  // namespace
}  // namespace ocp::vtime
