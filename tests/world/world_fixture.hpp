#pragma once
// Shared helpers for the world tests: ready-made configurations, a raw vehicle peer that
// speaks (or deliberately breaks) the vehicle-side protocol over a pipe, and small stepping
// helpers that find the exact virtual time something happened.
#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ocp/frame.hpp"
#include "ocp/json_codec.hpp"
#include "ocp/pipe.hpp"
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

// A hand-driven vehicle client on a pipe end: records every control frame (with arrival
// time), can echo, and can write arbitrary bytes. Its decoder is the libocp one.
class RawVehiclePeer {
 public:
  RawVehiclePeer(Executor& executor, std::shared_ptr<ByteStream> stream)
      : executor_(executor), stream_(std::move(stream)) {
    stream_->set_handlers(ByteStreamHandlers{
        [this](std::string_view bytes) { on_bytes(bytes); },
        [this](const std::string& reason) {
          closed_ = true;
          close_reason_ = reason;
          closed_at_ = executor_.now();
        }});
  }

  // Connects a new peer to the named vehicle's Streamer through a fresh pipe.
  static std::unique_ptr<RawVehiclePeer> connect(VirtualWorld& sim, const std::string& vehicle) {
    PipeOptions options;
    options.name_a = "pipe:raw-peer";
    options.name_b = "pipe:streamer";
    PipeEnds ends = make_pipe(sim.executor(), options);
    sim.world().accept_vehicle_connection(vehicle, ends.b);
    return std::make_unique<RawVehiclePeer>(sim.executor(), ends.a);
  }

  void write_raw(std::string_view bytes) { stream_->write(bytes); }
  void write_frame(std::string_view payload) {
    std::string frame;
    const std::uint32_t length = static_cast<std::uint32_t>(payload.size());
    for (int byte = 0; byte < 4; ++byte) frame.push_back(static_cast<char>((length >> (8 * byte)) & 0xff));
    frame.append(payload);
    stream_->write(frame);
  }
  void echo(const AckPair& pair) {
    VehicleResponseMessage response;
    response.ack = pair;
    std::string json;
    encode_vehicle_response(response, json);
    write_frame(json);
  }
  void close() { stream_->close(); }

  bool echo_automatically = false;
  bool closed() const { return closed_; }
  const std::string& close_reason() const { return close_reason_; }
  std::optional<SimTime> closed_at() const { return closed_at_; }
  const std::vector<SimTime>& control_times() const { return control_times_; }
  const std::vector<OcpControlMessage>& controls() const { return controls_; }
  std::uint64_t undecodable() const { return undecodable_; }

  // True when every control frame from index `from` on arrived exactly one tick after the
  // previous one.
  ::testing::AssertionResult cadence_exact(std::size_t from = 0) const {
    for (std::size_t index = from + 1; index < control_times_.size(); ++index) {
      const auto gap = control_times_[index] - control_times_[index - 1];
      if (gap != tick) {
        return ::testing::AssertionFailure()
               << "control frame " << index << " arrived " << gap.count() << " µs after the previous one at "
               << control_times_[index - 1].count() << " µs";
      }
    }
    return ::testing::AssertionSuccess() << control_times_.size() << " frames";
  }

 private:
  void on_bytes(std::string_view bytes) {
    while (!bytes.empty()) {
      FrameEvent event;
      bytes.remove_prefix(decoder_.put(bytes, event));
      if (event.kind == FrameEvent::Kind::need_more) return;
      if (event.kind != FrameEvent::Kind::frame) continue;
      auto decoded = decode_control_message(event.payload);
      if (!decoded) {
        ++undecodable_;
        continue;
      }
      control_times_.push_back(executor_.now());
      controls_.push_back(decoded.value());
      if (echo_automatically) echo(decoded->ack);
    }
  }

  Executor& executor_;
  std::shared_ptr<ByteStream> stream_;
  FrameDecoder decoder_;
  bool closed_ = false;
  std::string close_reason_;
  std::optional<SimTime> closed_at_;
  std::vector<SimTime> control_times_;
  std::vector<OcpControlMessage> controls_;
  std::uint64_t undecodable_ = 0;
};

}  // namespace ocp::world_test
