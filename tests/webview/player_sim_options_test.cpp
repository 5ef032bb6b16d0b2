// player_sim's web view and --vehicle-tcp options, run as a user would: every bad value is a
// clear error with exit code 2.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "child_process.hpp"

// tests/CMakeLists.txt defines the path of the built player_sim.
#if !defined(OCP_PLAYER_SIM_PATH)
#error "OCP_PLAYER_SIM_PATH must name the built player_sim"
#endif

namespace ocp {
namespace {

struct ProgramRun {
  int exit_code = -1;
  std::string output;
};

// Runs player_sim to completion (killed after 30 s), stdout and stderr together.
ProgramRun run_player_sim(std::vector<std::string> arguments) {
  arguments.insert(arguments.begin(), OCP_PLAYER_SIM_PATH);
  ocp::test::ChildProcess child(arguments);
  const int code = child.wait_exit(std::chrono::seconds(30));
  return ProgramRun{code >= 0 && code < 1000 ? code : -1, child.output()};
}

TEST(PlayerSimOptions, BadWebviewAndVehicleTcpValuesExitTwo) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases{
      {{"--webview-port", "-1"}, "--webview-port"},
      {{"--webview-port", "65536"}, "--webview-port"},
      {{"--webview-port", "nan"}, "--webview-port"},
      {{"--webview-port", ""}, "--webview-port"},
      {{"--webview-root", "/no/such/folder"}, "--webview-root"},
      {{"--webview-root", ""}, "--webview-root"},
      {{"--vehicle", "truck-1", "--vehicle-tcp", "truck-2=4000"}, "unknown vehicle 'truck-2'"},
      {{"--vehicle", "truck-1", "--vehicle-tcp", "truck-1=70000"}, "expected a port number 0..65535, got '70000'"},
      {{"--vehicle", "truck-1", "--vehicle-tcp", "truck-1"}, "expected NAME=PORT"},
      {{"--vehicle", "truck-1", "--vehicle-tcp", "truck-1=-5"}, "expected a port number"},
      {{"--webview-allow-origin", "localhost:8080"}, "--webview-allow-origin: expected an origin scheme://host[:port] (no '://'), got 'localhost:8080'"},
      {{"--webview-allow-origin", "http://localhost:8080/"}, "(no path, query or fragment, not even '/'), got 'http://localhost:8080/'"},
      {{"--webview-allow-origin", "http://localhost:8080/app"}, "no path"},
      {{"--webview-allow-origin", "http://me@localhost"}, "no user info"},
      {{"--webview-allow-origin", "http://localhost:99999"}, "the port is a number 1..65535"},
      {{"--webview-allow-origin", "http://"}, "no host"},
      {{"--webview-allow-origin", "*"}, "got '*'"},
      {{"--webview-allow-origin", "null"}, "got 'null'"},
      {{"--webview-allow-origin", ""}, "--webview-allow-origin"},
      {{"--webview-allow-origin", "http://localhost:8080", "--webview-allow-origin", "ftp//x"}, "got 'ftp//x'"},
  };
  for (const auto& [arguments, expected] : cases) {
    const ProgramRun run = run_player_sim(arguments);
    EXPECT_EQ(run.exit_code, 2) << arguments[0] << " " << arguments[1] << "\n" << run.output;
    EXPECT_NE(run.output.find(expected), std::string::npos) << run.output;
  }
}

TEST(PlayerSimOptions, HelpDocumentsTheWebviewOptions) {
  const ProgramRun run = run_player_sim({"--help"});
  EXPECT_EQ(run.exit_code, 0);
  for (const char* option : {"--webview-port", "--webview-root", "--no-webview", "--webview-allow-origin", "--vehicle-tcp"}) {
    EXPECT_NE(run.output.find(option), std::string::npos) << option;
  }
}

TEST(PlayerSimOptions, ServesTheWebviewAndAnExternalVehiclePortPickedByTheSystem) {
  const ProgramRun run = run_player_sim({"--vehicle", "truck-1", "--vehicle-tcp", "truck-1=0", "--webview-port", "0",
                                  "--plugin-param", "ocp_player_tcp_port", "0", "--duration-s", "0.5"});
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("web view on http://127.0.0.1:"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("vehicle API listening on 127.0.0.1:"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("truck-1 (external vehicle client on 127.0.0.1:"), std::string::npos) << run.output;
}

TEST(PlayerSimOptions, AllowedOriginsAreNormalisedAndLogged) {
  const ProgramRun run = run_player_sim({"--webview-port", "0", "--plugin-param", "ocp_player_tcp_port", "0",
                                         "--webview-allow-origin", "HTTP://LocalHost:8080", "--webview-allow-origin",
                                         "https://tools.example:443", "--duration-s", "0.3"});
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("web view: pages from http://localhost:8080, https://tools.example may use it too"),
            std::string::npos)
      << run.output;
}

}  // namespace
}  // namespace ocp
