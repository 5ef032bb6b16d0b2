#pragma once
// Running one scenario World with an external client process in virtual time, for the vtime
// tests (virtual_clients_test.cpp, thread_clients_test.cpp). Every run has a wall-clock
// watchdog (the Controller's), so a broken shim fails a test instead of hanging it.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <vector>

#include "scenario/parse.hpp"
#include "scenario/verdicts.hpp"
#include "vtime/client_world.hpp"

namespace ocp::vtime {

inline constexpr std::chrono::milliseconds test_watchdog{90'000};

inline std::string world_yaml(const std::string& duration, const std::string& expectations) {
  return "seed: 7\nduration: " + duration +
         "\nworld:\n  gamepad: drive\n  vehicles:\n    - name: truck-1\n      in_process_client: false\n"
         "      link: {delay: 10ms, jitter: 2ms}\nexpect:\n" +
         expectations;
}

inline const std::string echoing_client_expectations =
    "  faults:\n"
    "    - {fault: VehicleNoResponse, cleared: {after: 0s, within: 200ms}}\n"
    "    - {fault: InvalidMac, never: true, from: 1s}\n"
    "    - {fault: HighLatency, never: true}\n"
    "    - {fault: NoControlMessage, never: true}\n"
    "  thresholds:\n"
    "    latency_ms: [\"count > 900\", \"p(50) < 60\"]\n";

struct Ran {
  VirtualClientRun run;
  std::vector<scenario::Verdict> verdicts;
  double wall_seconds = 0;
};

inline Ran run_client(const std::string& yaml, std::vector<std::string> argv, ControllerOptions controller = {},
                      bool trace = false, const std::string& log_path = "") {
  const scenario::Scenario world = scenario::parse_scenario(yaml, "virtual.yaml");
  scenario::RunOptions options;
  options.trace = trace;
  VirtualClientOptions clients;
  clients.argv = std::move(argv);
  controller.shim_path = OCP_VTIME_SHIM_PATH;
  if (controller.watchdog == ControllerOptions{}.watchdog) controller.watchdog = test_watchdog;
  clients.controller = controller;
  if (!log_path.empty()) clients.log_path = [log_path](const std::string&) { return log_path; };
  const auto start = std::chrono::steady_clock::now();
  Ran ran;
  ran.run = run_with_virtual_clients(world, options, clients);
  ran.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ran.verdicts = scenario::evaluate(world, ran.run.result);
  return ran;
}

inline void expect_all_pass(const Ran& ran) {
  for (const scenario::Verdict& verdict : ran.verdicts) {
    EXPECT_TRUE(verdict.passed) << verdict.title << ": expected " << verdict.expected << ", got " << verdict.actual;
  }
}

inline std::string first_difference(const std::string& a, const std::string& b) {
  std::size_t at = 0;
  while (at < a.size() && at < b.size() && a[at] == b[at]) ++at;
  const std::size_t line = a.rfind('\n', at) + 1;
  return a.substr(line, a.find('\n', at) - line) + "\n" + b.substr(line, b.find('\n', at) - line);
}


}  // namespace ocp::vtime
