#pragma once
// Shared helpers for the world tests: ready-made configurations, a vehicle test peer on a
// pipe that speaks (or deliberately breaks) the vehicle-side protocol, and small stepping
// helpers that find the exact virtual time something happened.
#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ocp/pipe.hpp"
#include "vehicle_peer.hpp"
#include "world/stream_tap.hpp"
#include "world/virtual_world.hpp"

namespace ocp::world_test {

inline constexpr Micros tick{10'000};

inline VehicleSpec vehicle_spec(std::string name) {
  VehicleSpec spec;
  spec.name = std::move(name);
  return spec;
}

// One vehicle, no impairments, the reference client in-process, its stream tapped.
inline WorldConfig one_vehicle_config(std::uint64_t seed = 1) {
  WorldConfig config;
  config.seed = seed;
  config.tap_vehicle_streams = true;
  config.vehicles.push_back(vehicle_spec("truck-1"));
  return config;
}

// A gamepad state an operator would never leave by accident: clearly not the default.
inline Controller driving_controller() {
  Controller controller;
  controller.axes.right_trigger = 0.4;
  controller.axes.left_x = -0.25;
  controller.buttons.a = true;
  return controller;
}

inline Impairments delay_of(Micros delay) {
  Impairments impairments;
  impairments.delay = delay;
  return impairments;
}

// The golden trace's link (both directions): 15 ms ± 3 ms uniform jitter, 10 % loss.
inline Impairments jittery_lossy_link() {
  Impairments impairments;
  impairments.delay = Millis{15};
  impairments.jitter_kind = Impairments::JitterKind::uniform;
  impairments.jitter = Millis{3};
  impairments.loss_probability = 0.1;
  return impairments;
}

inline void set_down(ComChannel& link, bool to_streamer, bool down) {
  LinkDirection& direction = to_streamer ? link.to_streamer() : link.to_player();
  Impairments impairments = direction.impairments();
  impairments.down = down;
  direction.set_impairments(impairments);
}

// Steps one event at a time until `end`, returning the last time `counter` changed
// (nullopt if it never changed). Leaves now() == end.
inline std::optional<SimTime> last_change_until(VirtualWorld& sim, SimTime end,
                                                const std::function<std::uint64_t()>& counter) {
  std::optional<SimTime> changed;
  std::uint64_t value = counter();
  while (sim.executor().next_deadline() <= end) {
    sim.step();
    if (counter() != value) {
      value = counter();
      changed = sim.now();
    }
  }
  sim.run_until(end);
  return changed;
}

// First control tick strictly after `time` (ticks at k·10 ms from the world start at 0).
inline SimTime first_tick_after(SimTime time) {
  return SimTime{(time.count() / tick.count() + 1) * tick.count()};
}

// Time of the first JSON trace line containing `needle` (at or after not_before), or nullopt.
inline std::optional<SimTime> first_trace_time(const TraceRecorder& trace, const std::string& needle,
                                               SimTime not_before = SimTime{0}) {
  for (const std::string& line : trace.lines_containing(needle)) {
    const SimTime time = TraceRecorder::line_time(line);
    if (time >= not_before) return time;
  }
  return std::nullopt;
}

// A hand-driven vehicle peer connected to the named vehicle's Streamer through a fresh pipe
// (the Streamer sees "pipe:raw-peer"): records every control frame with its arrival time,
// can echo, and can write arbitrary bytes.
inline std::unique_ptr<testing::VehiclePeer> connect_vehicle_peer(VirtualWorld& sim, const std::string& vehicle) {
  PipeOptions options;
  options.name_a = "pipe:raw-peer";
  options.name_b = "pipe:streamer";
  PipeEnds ends = make_pipe(sim.executor(), options);
  sim.world().accept_vehicle_connection(vehicle, ends.b);
  auto peer = std::make_unique<testing::VehiclePeer>(&sim.executor());
  peer->attach(ends.a);
  return peer;
}

// True when every control frame from index `from` on arrived exactly one tick after the
// previous one.
inline ::testing::AssertionResult cadence_exact(const std::vector<SimTime>& arrivals, std::size_t from = 0) {
  for (std::size_t index = from + 1; index < arrivals.size(); ++index) {
    const auto gap = arrivals[index] - arrivals[index - 1];
    if (gap != tick) {
      return ::testing::AssertionFailure() << "control frame " << index << " arrived " << gap.count()
                                           << " µs after the previous one at " << arrivals[index - 1].count()
                                           << " µs";
    }
  }
  return ::testing::AssertionSuccess() << arrivals.size() << " frames";
}

}  // namespace ocp::world_test
