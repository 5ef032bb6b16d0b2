#pragma once
// Test harness for StreamerCore in virtual time: a StreamerCore on a VirtualExecutor, a
// minimal test-side vehicle on an in-memory pipe (libocp framing + JSON codec, exactly what a
// TCP client would send), and a fake Player that feeds handle_link_message and records what
// comes back over a zero-impairment LinkDirection.
#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "captured_log.hpp"
#include "ocp/com_channel.hpp"
#include "ocp/log.hpp"
#include "ocp/mac.hpp"
#include "ocp/pipe.hpp"
#include "ocp/virtual_executor.hpp"
#include "streamer/streamer_core.hpp"
#include "vehicle_peer.hpp"

namespace ocp::streamer_test {

inline constexpr SimTime ms(std::int64_t value) { return SimTime{value * 1000}; }

inline MacKey test_key() {
  MacKey key{};
  for (std::size_t i = 0; i < key.size(); ++i) key[i] = static_cast<std::uint8_t>(i * 7 + 1);
  return key;
}

inline StreamerConfig test_config() {
  StreamerConfig config;
  config.name = "truck-1";
  config.mac_key = test_key();
  return config;
}

// The vehicle end of each pipe: the shared test peer, failing the test on any frame that is
// not a control message.
using TestVehicle = testing::VehiclePeer;

struct Received {
  SimTime at;
  LinkMessage message;
};

// Records faults, connections and control frames from the Streamer's event stream.
class RecordingObserver {
 public:
  explicit RecordingObserver(EventBus& events)
      : subscription_(events.subscribe([this](const Event& event) { record(event); })) {}
  struct FaultChange {
    SimTime at;
    FaultId id;
    bool active;
  };
  // Times at which `id` changed to `active`.
  std::vector<SimTime> changes(FaultId id, bool active) const {
    std::vector<SimTime> times;
    for (const auto& change : fault_changes) {
      if (change.id == id && change.active == active) times.push_back(change.at);
    }
    return times;
  }
  std::vector<FaultChange> fault_changes;
  std::vector<std::pair<bool, std::string>> connections;   // opened (true) / closed, peer
  std::uint64_t controls_sent = 0;

 private:
  void record(const Event& event) {
    if (const auto* fault = std::get_if<FaultEvent>(&event.body)) {
      fault_changes.push_back({event.time, fault->id, fault->active});
    } else if (const auto* connection = std::get_if<ConnectionEvent>(&event.body)) {
      if (connection->change != ConnectionChange::refused) {
        connections.emplace_back(connection->change == ConnectionChange::opened,
                                 std::string(connection->peer));
      }
    } else if (const auto* frame = std::get_if<WireFrame>(&event.body)) {
      if (frame->direction == FrameDirection::out) ++controls_sent;
    }
  }
  EventBus::Subscription subscription_;
};

class StreamerHarness {
 public:
  explicit StreamerHarness(StreamerConfig config = test_config())
      : to_player(executor, 7),
        core(executor, std::move(config),
             Logger(executor, "streamer:truck-1", log.sink())),
        observer(core.events()) {
    to_player.set_receiver(
        [this](LinkMessage&& message) { from_streamer.push_back({executor.now(), std::move(message)}); });
    core.set_link(&to_player);
  }

  // Connects a new test vehicle through a pipe; the Streamer sees `peer_name`.
  TestVehicle& connect_vehicle(std::string peer_name = "pipe:vehicle") {
    PipeOptions options;
    options.name_a = std::move(peer_name);
    options.name_b = "pipe:streamer";
    PipeEnds ends = make_pipe(executor, options);
    vehicles.push_back(std::make_unique<TestVehicle>(&executor));
    vehicles.back()->fail_on_undecodable = true;
    vehicles.back()->attach(ends.a);
    core.accept_vehicle_connection(ends.b);
    return *vehicles.back();
  }

  void send_control(OperatorControl control) { core.handle_link_message(std::move(control)); }

  // Schedules an operator message at first, first + period, … ≤ last, built at send time.
  void schedule_controls(SimTime first, SimTime last, Micros period,
                         std::function<OperatorControl(SimTime now)> make) {
    for (SimTime at = first; at <= last; at += period) {
      executor.call_at(at, [this, make, at] { send_control(make(at)); });
    }
  }

  // Operator messages every 10 ms at 5 ms past each tick, returning a fresh valid pair
  // (issued `age` before the message) and `controller`.
  void schedule_fresh_controls(SimTime first, SimTime last, std::optional<Controller> controller,
                               Micros age = Micros{5000}) {
    schedule_controls(first, last, Micros{10'000}, [this, controller, age](SimTime now) {
      return control_returning(pair_issued_at(now - age), controller);
    });
  }

  // An operator message returning `pair` (valid unless the caller tampers with it).
  OperatorControl control_returning(std::optional<AckPair> pair,
                                    std::optional<Controller> controller = Controller{}) {
    OperatorControl control;
    control.sequence = next_sequence_++;
    control.controller = std::move(controller);
    control.returned_ack = pair;
    return control;
  }

  // A valid pair as the Streamer would have issued it at `issued_at` (offset from config).
  AckPair pair_issued_at(SimTime issued_at) {
    const std::uint64_t ack_time =
        static_cast<std::uint64_t>(issued_at.count()) + core.config().ack_time_offset;
    AckMac mac(*core.config().mac_key);
    return AckPair{ack_time, mac.compute(ack_time)};
  }

  template <class T>
  std::vector<std::pair<SimTime, T>> received_of() const {
    std::vector<std::pair<SimTime, T>> out;
    for (const auto& item : from_streamer) {
      if (const auto* value = std::get_if<T>(&item.message)) out.emplace_back(item.at, *value);
    }
    return out;
  }

  bool logged(std::string_view needle) const { return log.contains(needle); }

  VirtualExecutor executor;
  LinkDirection to_player;
  testing::CapturedLog log;  // before core: its logger holds the sink
  StreamerCore core;
  RecordingObserver observer;
  std::vector<std::unique_ptr<TestVehicle>> vehicles;
  std::vector<Received> from_streamer;

 private:
  std::uint64_t next_sequence_ = 0;
};

}  // namespace ocp::streamer_test
