// The built streamer_sim and player_sim executables, run as a user would: --help, bad options,
// a busy port, --duration-s and SIGTERM, checked by exit code and output.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/joystick.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "ocp/asio/tcp_server.hpp"
#include "child_process.hpp"
#include "tcp_peers.hpp"

extern char** environ;

// tests/CMakeLists.txt defines the paths of the built executables.
#if !defined(OCP_STREAMER_SIM_PATH) || !defined(OCP_PLAYER_SIM_PATH)
#error "OCP_STREAMER_SIM_PATH and OCP_PLAYER_SIM_PATH must name the built streamer_sim and player_sim"
#endif

namespace ocp {
namespace {

constexpr std::chrono::seconds process_timeout{30};

// A program under test, its output on a pipe (tests/support/child_process.hpp).
struct Process {
  std::unique_ptr<ocp::test::ChildProcess> child;

  static Process spawn(const std::vector<std::string>& arguments) {
    Process process;
    process.child = std::make_unique<ocp::test::ChildProcess>(arguments);
    EXPECT_TRUE(process.child->started()) << "cannot start " << arguments[0];
    return process;
  }
  // Exit code, or -1 if it had to be killed after the timeout (or died by a signal).
  int wait(std::chrono::milliseconds timeout = process_timeout) {
    const int code = child->wait_exit(timeout);
    return code >= 0 && code < 1000 ? code : -1;
  }
  void signal(int number) { child->signal(number); }
  std::string output() const { return child->output(); }
};

struct ProcessRun {
  int exit_code;
  std::string output;
};

ProcessRun run(const std::vector<std::string>& arguments) {
  Process process = Process::spawn(arguments);
  const int code = process.wait();
  return {code, process.output()};
}

// A port nobody listens on right now (taken from the kernel, then released).
std::uint16_t free_port() {
  boost::asio::io_context io;
  TcpServer server(io, {});
  EXPECT_TRUE(server.listen({.port = 0}).ok());
  return server.port();
}

bool can_connect(std::uint16_t port) {
  boost::asio::io_context io;
  std::string error;
  return testing::connect_loopback(io, port, error) != nullptr;
}

const std::string streamer_sim = OCP_STREAMER_SIM_PATH;
const std::string player_sim = OCP_PLAYER_SIM_PATH;
const std::string vehicle_client = OCP_VEHICLE_CLIENT_PATH;

TEST(Executables, HelpExitsZeroAndListsThePluginParameters) {
  for (const auto& program : {streamer_sim, player_sim}) {
    const ProcessRun result = run({program, "--help"});
    EXPECT_EQ(result.exit_code, 0) << program;
    EXPECT_NE(result.output.find("--plugin-param NAME VALUE"), std::string::npos) << result.output;
    EXPECT_NE(result.output.find("ocp_tcp_allow_remote"), std::string::npos);
  }
}

TEST(Executables, UnknownOptionOrBadValueExitsTwoWithAClearError) {
  for (const auto& program : {streamer_sim, player_sim}) {
    ProcessRun result = run({program, "--no-such-option"});
    EXPECT_EQ(result.exit_code, 2) << program;
    EXPECT_NE(result.output.find("--no-such-option"), std::string::npos) << result.output;

    result = run({program, "--plugin-param", "tcp_port", "forty"});
    EXPECT_EQ(result.exit_code, 2) << program;
    EXPECT_NE(result.output.find("tcp_port: expected a port number 0..65535, got 'forty'"), std::string::npos)
        << result.output;

    result = run({program, "--plugin-param", "tcp_prot", "4000"});
    EXPECT_EQ(result.exit_code, 2) << program;
    EXPECT_NE(result.output.find("unknown plugin parameter 'tcp_prot'"), std::string::npos) << result.output;

    result = run({program, "--link-loss", "1.5"});
    EXPECT_EQ(result.exit_code, 2) << program;
  }
}

TEST(Executables, BusyPortExitsTwoNamingTheAddress) {
  boost::asio::io_context io;
  TcpServer occupant(io, {});
  ASSERT_TRUE(occupant.listen({.port = 0}).ok());
  const std::string port = std::to_string(occupant.port());

  ProcessRun result = run({streamer_sim, "--plugin-param", "tcp_port", port, "--duration-s", "20"});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("cannot start: another socket listens on 127.0.0.1:" + port + " (is another"), std::string::npos)
      << result.output;

  EXPECT_NE(result.output.find("pick another port with --plugin-param tcp_port N"), std::string::npos) << result.output;

  result = run({player_sim, "--plugin-param", "ocp_player_tcp_port", port, "--duration-s", "20"});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("cannot start: another socket listens on 127.0.0.1:" + port + " (is another"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("pick another port with --plugin-param ocp_player_tcp_port N"), std::string::npos)
      << result.output;
}

// Each port player_sim opens names its own option when it is busy (not ocp_player_tcp_port's).
TEST(Executables, BusyWebviewOrVehicleTcpPortNamesItsOwnOption) {
  boost::asio::io_context io;
  TcpServer occupant(io, {});
  ASSERT_TRUE(occupant.listen({.port = 0}).ok());
  const std::string port = std::to_string(occupant.port());

  ProcessRun result = run({player_sim, "--plugin-param", "ocp_player_tcp_port", "0", "--webview-port", port, "--duration-s", "20"});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("pick another port with --webview-port N"), std::string::npos) << result.output;
  EXPECT_EQ(result.output.find("ocp_player_tcp_port N"), std::string::npos) << result.output;

  result = run({player_sim, "--plugin-param", "ocp_player_tcp_port", "0", "--no-webview", "--vehicle-tcp", "vehicle=" + port,
                "--duration-s", "20"});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("pick another port with --vehicle-tcp vehicle=PORT"), std::string::npos) << result.output;
}

// SIGTERM, and SIGHUP (a closed SSH session, a CI runner's cancel) the same way: a clean
// shutdown with exit 0, not 129 and no goodbye.
TEST(Executables, SigtermOrSighupShutsDownCleanlyWithExitZero) {
  for (const auto& [signal_number, name] : {std::pair{SIGTERM, "SIGTERM"}, std::pair{SIGHUP, "SIGHUP"}}) {
    SCOPED_TRACE(name);
    const std::uint16_t port = free_port();
    Process process = Process::spawn({streamer_sim, "--plugin-param", "tcp_port", std::to_string(port)});
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (!can_connect(port) && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    ASSERT_TRUE(can_connect(port)) << process.output();
    process.signal(signal_number);
    EXPECT_EQ(process.wait(), 0) << process.output();
    const std::string output = process.output();
    EXPECT_NE(output.find(std::string("shutting down: ") + name + " received"), std::string::npos) << output;
    EXPECT_NE(output.find("vehicle connected: 127.0.0.1:"), std::string::npos) << output;
  }
}

TEST(Executables, DurationRunsPrintsStatusLinesAndExitsZero) {
  const ProcessRun result = run({player_sim, "--plugin-param", "ocp_player_tcp_port", "0", "--webview-port", "0", "--vehicle", "truck-1",
                          "--vehicle", "truck-2", "--duration-s", "2.2"});
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("operator API listening on 127.0.0.1:"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("status: operator client none"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("truck-2: simulated Streamer: latency"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("operator client sees: receiver_fault"), std::string::npos) << result.output;
}

// --gamepad js:DEVICE: a real joystick reaches the wire. A FIFO carrying js_event records stands
// in for /dev/input/js0 (the reader cannot tell them apart); what it says must arrive in the
// control messages that the vehicle client receives. A device that is not there is a usage error.
TEST(Executables, JoystickDeviceDrivesTheControlMessages) {
  ProcessRun missing = run({streamer_sim, "--gamepad", "js:/nonexistent/js9", "--duration-s", "1"});
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_NE(missing.output.find("no joystick device at '/nonexistent/js9'"), std::string::npos) << missing.output;

  char pattern[] = "/tmp/ocp-js-XXXXXX";
  ASSERT_NE(mkdtemp(pattern), nullptr);
  const std::string directory = pattern, device = directory + "/js0", wire = directory + "/wire.jsonl";
  ASSERT_EQ(mkfifo(device.c_str(), 0600), 0);
  const int writer = ::open(device.c_str(), O_RDWR | O_CLOEXEC);   // never blocks; holds the events
  ASSERT_GE(writer, 0);
  for (const js_event event : {js_event{0, 1, JS_EVENT_BUTTON, 0}, js_event{0, -32767, JS_EVENT_AXIS, 0}}) {
    ASSERT_EQ(::write(writer, &event, sizeof event), static_cast<ssize_t>(sizeof event));   // a pressed, left_x -1
  }
  const std::uint16_t port = free_port();
  Process streamer = Process::spawn({streamer_sim, "--plugin-param", "tcp_port", std::to_string(port), "--gamepad", "js:" + device,
                                     "--wire-log", wire, "--duration-s", "4"});
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (!can_connect(port) && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  const ProcessRun client = run({vehicle_client, "127.0.0.1:" + std::to_string(port), "--duration-s", "2", "--no-status"});
  EXPECT_EQ(streamer.wait(), 0) << streamer.output();
  std::ifstream in(wire);
  std::stringstream text;
  text << in.rdbuf();
  const std::string frames = text.str();
  // The payload is a JSON string inside each line, so its quotes come escaped.
  EXPECT_NE(frames.find(R"(\"a\":true)"), std::string::npos) << streamer.output() << client.output;
  EXPECT_NE(frames.find(R"(\"left_x\":-1)"), std::string::npos) << streamer.output();
  ::close(writer);
  std::filesystem::remove_all(directory);
}

}  // namespace
}  // namespace ocp
