#pragma once
// `ocp_bench fleet`: the scale curve — N vehicles in one process over real loopback TCP at
// 100 Hz, and the same in virtual time; tick lateness, echo delay, CPU per simulated second,
// memory per vehicle, faults, each thread's CPU; a table, --json and an SVG of the curve (--svg).
#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

namespace ocp::bench {

struct FleetOptions {
  std::vector<int> loopback_vehicles{1, 10, 100};
  std::vector<int> virtual_vehicles{1, 10, 100};
  double window_s = 5.0;           // loopback: wall seconds measured per point
  double simulated_s = 10.0;       // virtual: simulated seconds measured per point
  double warm_up_s = 1.0;          // run before measuring (both modes)
  double point_timeout_s = 180.0;  // a point still running after this is killed and reported
  bool unobserved = false;         // virtual points without subscribing (the world's own speed)
  int streamer_threads = 2;        // loopback: threads hosting the Streamers (0: the main thread)
  // Loopback: threads hosting the reference clients (0: the Streamers' own); unset: as many as
  // --streamer-threads, at least 1, so a fleet given more Streamer threads gets client threads
  // to match (one client thread for a whole fleet was the saturated thread of issue #41).
  std::optional<int> client_threads;
  // Loopback: WorldConfig::control_tick_slots (0: a timer per Streamer); unset: one slot per
  // vehicles_per_tick_slot vehicles of a Streamer thread, 1 to 10 (auto_tick_slots).
  std::optional<int> tick_slots;
  bool kernel_floor = true;        // loopback: measure the kernel's TCP cost of the traffic after each point
  bool codec_floor = true;         // virtual, observed: measure the wire codec's cost alone after each point
  bool in_process = false;         // run points in this process (for profilers); memory then accumulates
  std::string json_path, svg_path;
};

// Slots spread a big fleet's ticks over the period so that the last vehicle of a slot is not
// late by the whole fleet's work; each slot is also a wake-up of its thread per period (~20 µs
// of CPU on a VM). A slot of 10 vehicles costs a tick about 0.1 ms of lateness, as 10 slots of
// 5 did at N = 100, for half the wake-ups (docs/benchmarks.md, issue #41).
constexpr int vehicles_per_tick_slot = 10;
constexpr int max_auto_tick_slots = 10;
int auto_tick_slots(int vehicles, int streamer_threads);

CLI::App* add_fleet_command(CLI::App& app, FleetOptions& options);
int run_fleet(const FleetOptions& options);

}  // namespace ocp::bench
