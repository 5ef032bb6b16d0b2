#pragma once
// Runs of the built ocp_conformance against a client, for the suite's tests (suite_test.cpp,
// virtual_time_test.cpp): the exit code, the output and index.json of one bounded run.
#include <gtest/gtest.h>
#include <rapidjson/document.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "node_program.hpp"

namespace ocp::conformance_test {

inline const std::string harness = OCP_CONFORMANCE_PATH;
inline const std::string reference = OCP_VEHICLE_CLIENT_PATH;
inline const std::string broken = OCP_BROKEN_CLIENT_PATH;

inline std::string fresh_dir(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/conformance_" + name + "_" + std::to_string(getpid());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Runs a shell command (bounded by `timeout`), returns its exit code; output goes to `log`.
inline int run(const std::string& command, const std::string& log) {
  const std::string line = "timeout -k 5 180 " + command + " > " + log + " 2>&1";
  const int status = std::system(line.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

struct SuiteRun {
  int exit_code = -1;
  rapidjson::Document index;
  std::string output;
  std::string verdict(const std::string& id) const {
    if (!index.IsObject()) return "no index.json";
    for (const auto& c : index["cases"].GetArray()) {
      if (id == c["id"].GetString()) return c["verdict"].GetString();
    }
    return "not run";
  }
};

inline SuiteRun run_suite(const std::string& name, const std::string& options, const std::string& client,
                   const std::string& suite = "vehicle") {
  const std::string dir = fresh_dir(name);
  SuiteRun result;
  // A Python client took 3.9 s to start on this machine at load 9: the suites here give every
  // client 60 s to connect, so only the tests of the connect timeout itself depend on it.
  const std::string connect = options.find("--connect-timeout-s") == std::string::npos ? " --connect-timeout-s 60" : "";
  // The tool's default with a launched client is virtual time; a run that names no time is one
  // of the real-time runs (virtual_time_test.cpp and the coverage rows name theirs).
  const std::string time = options.find("--time") == std::string::npos ? " --time real" : "";
  result.exit_code =
      run(harness + " " + suite + " --out " + dir + connect + time + " " + options + " -- " + client, dir + "/out.txt");
  result.output = read_file(dir + "/out.txt");
  const std::string json = read_file(dir + "/index.json");
  result.index.Parse<rapidjson::kParseValidateEncodingFlag>(json.c_str());   // reports stay valid UTF-8
  if (result.index.HasParseError()) result.index.SetNull();
  return result;
}

inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

inline std::string python_client(const std::string& mode) { return "python3 " + broken + " " + mode + " {port}"; }

// Every case of a run is OK, but for `allowed` (case id → the verdict it may get instead): the
// one check behind the reference client's and the example clients' runs. Prints the per-case
// durations. Returns the number of cases.
inline std::size_t expect_every_case_ok(const SuiteRun& r, const std::map<std::string, std::string>& allowed = {}) {
  std::size_t cases = 0;
  if (!r.index.IsObject()) {
    ADD_FAILURE() << "no index.json: " << r.output;
    return 0;
  }
  for (const auto& c : r.index["cases"].GetArray()) {
    ++cases;
    const std::string id = c["id"].GetString(), verdict = c["verdict"].GetString();
    const auto other = allowed.find(id);
    if (other != allowed.end() && verdict == other->second) {
      std::printf("  note: %s %s on this machine: %s\n", id.c_str(), verdict.c_str(), c["actual"].GetString());
    } else {
      EXPECT_EQ(verdict, "OK") << id << ": " << c["actual"].GetString();
    }
    std::printf("  %-14s %6.0f ms  %s\n", id.c_str(), c["duration_ms"].GetDouble(), verdict.c_str());
  }
  std::printf("  suite: %.1f s\n", r.index["duration_ms"].GetDouble() / 1000.0);
  return cases;
}

// The minimal Python clients of examples/ (written from docs/protocol.md alone) pass the
// suites: the docs' first steps are tested.
inline std::string example_client(const std::string& file) {
  return "python3 " + std::string(OCP_EXAMPLES_DIR) + "/" + file + " 127.0.0.1:{port}";
}
// The same for the Node.js examples (OCP_SKIP_WITHOUT_NODE() first).
inline std::string node_example_client(const std::string& file) {
  return ocp::testing::node_program() + " " + std::string(OCP_EXAMPLES_DIR) + "/" + file + " 127.0.0.1:{port}";
}

}  // namespace ocp::conformance_test
