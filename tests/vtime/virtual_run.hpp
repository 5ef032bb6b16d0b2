#pragma once
// Running one scenario World with an external client process in virtual time, for the vtime
// tests (virtual_clients_test.cpp, thread_clients_test.cpp). Every run has a wall-clock
// watchdog (the Controller's), so a broken shim fails a test instead of hanging it.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
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

// One world of OCP_VTIME_BENCH_SECONDS (10 by default; docs/benchmarks.md) with `argv` as its
// client: every expectation passes, and the simulated-to-wall ratio is printed with where the
// wall time went (the world only: the process's start-up and the harness are not in it).
inline Ran expect_echoes(const std::string& name, const std::vector<std::string>& argv) {
  const char* set = std::getenv("OCP_VTIME_BENCH_SECONDS");
  const int seconds = set != nullptr && std::atoi(set) > 0 ? std::atoi(set) : 10;
  std::string expectations = echoing_client_expectations;
  expectations.replace(expectations.find("count > 900"), 11, "count > " + std::to_string(seconds * 90));
  Ran ran = run_client(world_yaml(std::to_string(seconds) + "s", expectations), argv);
  EXPECT_EQ(ran.run.result.ran, Micros{seconds * 1'000'000LL});
  expect_all_pass(ran);
  const ControllerStats& stats = ran.run.stats;
  std::printf("%s: %d s simulated in %.2f s wall (%.0fx); run %.0f ms: quiescence waits %.0f ms (/proc looks %.0f ms), "
              "simulator and exchange %.0f ms; %llu instants, %llu settles, %llu /proc looks (%llu single), %llu shim messages\n",
              name.c_str(), seconds, ran.wall_seconds, seconds / ran.wall_seconds, stats.run_us / 1000.0, stats.settle_us / 1000.0,
              stats.proc_us / 1000.0, (static_cast<double>(stats.run_us) - static_cast<double>(stats.settle_us)) / 1000.0,
              static_cast<unsigned long long>(stats.instants), static_cast<unsigned long long>(stats.settles),
              static_cast<unsigned long long>(stats.proc_checks), static_cast<unsigned long long>(stats.single_looks),
              static_cast<unsigned long long>(stats.messages));
  return ran;
}

inline std::string first_difference(const std::string& a, const std::string& b) {
  std::size_t at = 0;
  while (at < a.size() && at < b.size() && a[at] == b[at]) ++at;
  const std::size_t line = a.rfind('\n', at) + 1;
  return a.substr(line, a.find('\n', at) - line) + "\n" + b.substr(line, b.find('\n', at) - line);
}


}  // namespace ocp::vtime
