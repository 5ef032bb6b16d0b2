// The minimal Python clients of examples/ (written from docs/protocol.md) pass the conformance
// suites: examples/vehicle_client.py the vehicle suite, examples/operator_client.py the
// operator suite. Every run is bounded by `timeout`, so a hanging harness fails the test.
#include <gtest/gtest.h>
#include <rapidjson/document.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

const std::string harness = OCP_CONFORMANCE_PATH;
const std::string examples = OCP_EXAMPLES_DIR;

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

struct SuiteRun {
  int exit_code = -1;
  std::string output;
  rapidjson::Document index;
};

// The whole suite, two workers, against `python3 examples/<client> 127.0.0.1:{port}`.
SuiteRun run_suite(const std::string& suite, const std::string& client) {
  const std::string dir = ::testing::TempDir() + "/example_" + suite + "_" + std::to_string(getpid());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string command = "timeout -k 5 180 " + harness + " " + suite + " -j 2 --out " + dir +
                              " -- python3 " + examples + "/" + client + " 127.0.0.1:{port} > " + dir +
                              "/out.txt 2>&1";
  const int status = std::system(command.c_str());
  SuiteRun run;
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.output = read_file(dir + "/out.txt");
  const std::string json = read_file(dir + "/index.json");
  run.index.Parse(json.c_str());
  if (run.index.HasParseError()) run.index.SetNull();
  return run;
}

TEST(ExampleClient, VehicleClientPassesTheVehicleSuite) {
  const SuiteRun r = run_suite("vehicle", "vehicle_client.py");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(r.index.IsObject()) << r.output;
  std::size_t cases = 0;
  for (const auto& c : r.index["cases"].GetArray()) {
    ++cases;
    const std::string id = c["id"].GetString(), verdict = c["verdict"].GetString();
    // The echo-delay median is wall-clock: on a box busy with builds a NON-STRICT there is the
    // machine, not the client (as for the reference client); every other case must be OK.
    if (id == "vehicle/3.3/2" && verdict == "NON-STRICT") {
      std::printf("  note: %s NON-STRICT on this machine: %s\n", id.c_str(), c["actual"].GetString());
    } else {
      EXPECT_EQ(verdict, "OK") << id << ": " << c["actual"].GetString();
    }
    std::printf("  %-14s %6.0f ms  %s\n", id.c_str(), c["duration_ms"].GetDouble(), verdict.c_str());
  }
  EXPECT_GE(cases, 16u);
}

TEST(ExampleClient, OperatorClientPassesTheOperatorSuite) {
  const SuiteRun r = run_suite("operator", "operator_client.py");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(r.index.IsObject()) << r.output;
  std::size_t cases = 0;
  for (const auto& c : r.index["cases"].GetArray()) {
    ++cases;
    const std::string id = c["id"].GetString(), verdict = c["verdict"].GetString();
    // The INFO case only reports; the example never disables the gamepad, so 4.4/1 has
    // nothing to check. It does send user_data, so 4.2/5 is graded.
    const std::string expected = id == "operator/4.2/6" || id == "operator/4.4/1" ? "INFORMATIONAL" : "OK";
    EXPECT_EQ(verdict, expected) << id << ": " << c["actual"].GetString();
    std::printf("  %-14s %6.0f ms  %s\n", id.c_str(), c["duration_ms"].GetDouble(), verdict.c_str());
  }
  EXPECT_GE(cases, 15u);
}

}  // namespace
