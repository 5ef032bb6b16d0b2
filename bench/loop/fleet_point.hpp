#pragma once
// One point of the fleet scale curve: N vehicles hosted by one process, either over real
// loopback TCP (N Streamers on --streamer-threads threads, N reference clients on --client-threads others,
// real time) or in virtual time (a World with N in-process clients over pipes). Each point runs in a forked
// child (fleet_command.cpp), so CPU and resident memory are that point's alone; the result is
// a plain struct sent back through a pipe.
#include <cstdint>
#include <string>

#include "fleet_recorder.hpp"
#include "kernel_floor.hpp"
#include "thread_usage.hpp"

namespace ocp::bench {

enum class FleetMode : std::uint8_t { loopback, virtual_time };

struct FleetPointOptions {
  FleetMode mode = FleetMode::loopback;
  int vehicles = 1;
  double warm_up_s = 1.0;
  double window_s = 5.0;        // wall seconds (loopback) or simulated seconds (virtual)
  double connect_timeout_s = 60.0;
  // Subscribe to the events. Publishing a WireFrame extracts its pair (a JSON decode of every
  // frame), so observing costs the world real work; false measures the world alone.
  bool observe = true;
  // Loopback: threads the Streamers are spread over (World::set_streamer_threads); the Player
  // stays on the main thread, the clients on their own. 0: everything on the main thread.
  int streamer_threads = 2;
  // Loopback: threads the reference clients are spread over, each with its own io_context;
  // 0: each client on its own Streamer's executor.
  int client_threads = 1;
  // WorldConfig::control_tick_slots: one shared control ticker per executor with this many
  // slots over the 10 ms period (0: a timer per Streamer). Loopback only: in virtual time the
  // reference clients' keep-alive timers (response_period = 10 ms) fire just before control
  // frames that arrive off their phase, doubling the responses, so virtual points keep 0.
  std::size_t control_tick_slots = 10;
  // Loopback: seconds of kernel-floor rounds (kernel_floor.hpp) run after the point's window,
  // once its sockets are closed, with frames of the sizes the point sent, then of the paced
  // floor (at least paced_floor_min_s); 0: neither is measured.
  double kernel_floor_s = 0.4;
  // Virtual, observed: seconds of codec-floor rounds (codec_floor.hpp) run after the window on
  // message samples the point sent; 0: not measured.
  double codec_floor_s = 0.4;
};

// The paced kernel floor's shape for a point: a server thread per Streamer thread (at least one,
// none without a vehicle), its ticker slots as bursts (a timer per Streamer, slots 0, paces
// like one slot), the clients' ends on threads of their own unless --client-threads 0. The
// floor is measured in it and the report names it, from the same fields.
PacedShape paced_floor_shape(int vehicles, int streamer_threads, int client_threads, int tick_slots);

// Trivially copyable: written as bytes through a pipe.
struct FleetPointResult {
  FleetMode mode = FleetMode::loopback;
  int vehicles = 0;
  bool observed = true;
  int streamer_threads = 0;
  int client_threads = 0;
  int control_tick_slots = 0;
  bool ok = false;
  char error[160] = {};
  double window_s = 0;            // what was measured: wall (loopback) or simulated (virtual) s
  double wall_s = 0;
  double cpu_s = 0;
  double cpu_per_simulated_s = 0;
  double simulated_per_wall_s = 0;
  double rss_base_kib = 0, rss_end_kib = 0, kib_per_vehicle = 0;
  double marginal_kib_per_vehicle = 0;   // against the previous point of the same mode (fleet_command)
  double tick_p50_us = 0, tick_p99_us = 0, tick_max_us = 0;
  double echo_p50_us = 0, echo_p99_us = 0;
  std::uint64_t ticks = 0, echoes = 0, responses = 0, connections = 0;
  double control_bytes = 0, response_bytes = 0;   // mean on the wire, over the window
  // Kernel floor (loopback): CPU of the kernel's TCP work alone for this traffic.
  bool kernel_floor_measured = false;
  char kernel_floor_error[120] = {};
  double kernel_floor_us_per_vehicle_tick = 0;
  double kernel_floor_cpu_per_s = 0;               // CPU s per wall s at 100 Hz × vehicles
  // The same traffic paced as the point runs it (kernel_floor.hpp, PacedShape): its threads, its
  // slots, at 100 Hz.
  bool paced_floor_measured = false;
  char paced_floor_error[120] = {};
  double paced_floor_us_per_vehicle_tick = 0;
  double paced_floor_cpu_per_s = 0;
  double paced_floor_wall_s = 0;                   // its measured periods: at least 10 ms each
  // Codec floor (virtual): CPU of the wire codec and MAC work alone for this fleet.
  bool codec_floor_measured = false;
  char codec_floor_error[120] = {};
  double codec_floor_us_per_vehicle_cycle = 0;
  double codec_floor_cpu_per_s = 0;                // CPU s per simulated s
  std::uint64_t faults_raised[fault_count] = {};
  // Each thread of the point's process over the window (thread_usage.hpp): the Player's (the
  // main thread, "player"), the Streamers' ("streamers-i"), the clients' ("clients-i").
  int thread_count = 0;
  ThreadSample threads[160] = {};
  std::uint64_t faults_total() const;
};

FleetPointResult run_fleet_point(const FleetPointOptions& options);
std::string fleet_mode_name(FleetMode mode);   // "loopback" | "virtual"

}  // namespace ocp::bench
