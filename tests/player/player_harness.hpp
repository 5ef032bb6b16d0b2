#pragma once
// Test harness for PlayerCore in virtual time: links with zero impairments whose receivers
// record what the Player sends, helpers to feed Streamer messages, the captured log, and an
// operator peer over an in-memory pipe that speaks the real framing + codec.
#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "captured_log.hpp"
#include "ocp/com_channel.hpp"
#include "ocp/log.hpp"
#include "operator_peer.hpp"
#include "ocp/pipe.hpp"
#include "ocp/virtual_executor.hpp"
#include "player/player_core.hpp"

namespace ocp::testing {

inline SimTime at_ms(std::int64_t ms) { return SimTime{ms * 1000}; }

struct Sent {
  SimTime time;
  LinkMessage message;
};

class PlayerHarness {
 public:
  explicit PlayerHarness(PlayerConfig config = {})
      : player(executor, std::move(config),
               Logger(executor, "player", log.sink())) {}

  Status add_vehicle(const std::string& name, bool monitor = false) {
    auto link = std::make_unique<LinkDirection>(executor, 1000 + links_.size());
    link->set_receiver([this, name](LinkMessage&& message) {
      if (const auto* ping = std::get_if<Ping>(&message); ping && pong_delay) {
        const Pong pong{ping->id, ping->sent_at};
        executor.call_after(*pong_delay, [this, name, pong] {
          player.handle_link_message(name, LinkMessage{pong});
        });
      }
      sent[name].push_back({executor.now(), std::move(message)});
    });
    LinkDirection* raw = link.get();
    links_[name] = std::move(link);
    return player.add_vehicle(name, raw, monitor);
  }

  std::vector<std::pair<SimTime, OperatorControl>> controls(const std::string& name) const {
    std::vector<std::pair<SimTime, OperatorControl>> out;
    const auto found = sent.find(name);
    if (found == sent.end()) return out;
    for (const Sent& item : found->second) {
      if (const auto* control = std::get_if<OperatorControl>(&item.message)) {
        out.emplace_back(item.time, *control);
      }
    }
    return out;
  }

  // The control message sent in the frame at `time` (exactly), or nullopt.
  std::optional<OperatorControl> control_at(const std::string& name, SimTime time) const {
    for (auto& [when, control] : controls(name)) {
      if (when == time) return control;
    }
    return std::nullopt;
  }

  std::vector<Ping> pings(const std::string& name) const {
    std::vector<Ping> out;
    const auto found = sent.find(name);
    if (found == sent.end()) return out;
    for (const Sent& item : found->second) {
      if (const auto* ping = std::get_if<Ping>(&item.message)) out.push_back(*ping);
    }
    return out;
  }

  // Schedules a Streamer message to arrive at `time`.
  void deliver_at(SimTime time, const std::string& vehicle, LinkMessage message) {
    executor.call_at(time, [this, vehicle, message = std::move(message)]() mutable {
      player.handle_link_message(vehicle, std::move(message));
    });
  }
  void video_at(SimTime time, const std::string& vehicle, std::optional<AckPair> sei,
                const std::string& camera = "front") {
    VideoFrame frame;
    frame.camera = camera;
    frame.sei = sei;
    deliver_at(time, vehicle, LinkMessage{frame});
  }
  void client_data_at(SimTime time, ClientSource source, ClientOcpShared data) {
    executor.call_at(time, [this, source, data = std::move(data)] {
      player.handle_client_data(source, data);
    });
  }

  void run_until(SimTime end) { executor.run_until(end); }

  bool logged(LogLevel level, const std::string& needle) const { return log.contains(level, needle); }
  const CapturedLog::Line* find_log(LogLevel level, const std::string& needle) const {
    return log.find(level, needle);
  }

  VirtualExecutor executor;
  CapturedLog log;  // before player: its logger holds the sink
  std::map<std::string, std::vector<Sent>> sent;
  std::optional<Micros> pong_delay;  // when set, every Ping is answered after this delay
  PlayerCore player;

 private:
  std::map<std::string, std::unique_ptr<LinkDirection>> links_;
};

inline ClientOcpShared client_entry(const std::string& vehicle, ClientVehicleEntry entry,
                                    std::optional<std::string> active = std::nullopt) {
  ClientOcpShared data;
  data.active_vehicle = std::move(active);
  data.client_user_data.emplace(vehicle, std::move(entry));
  return data;
}

// An operator peer attached to the harness's Player through an in-memory pipe: it speaks
// exactly what a TCP client on :4001 speaks.
class TestOperatorClient : public OperatorPeer {
 public:
  TestOperatorClient(PlayerHarness& harness, std::string name = "pipe:operator-1",
                     std::size_t max_chunk_bytes = 0)
      : OperatorPeer(&harness.executor) {
    PipeOptions options;
    options.name_b = std::move(name);  // the Player's end sees this peer name
    options.max_chunk_bytes = max_chunk_bytes;
    PipeEnds ends = make_pipe(harness.executor, options);
    attach(ends.b);
    harness.player.accept_client_connection(ends.a);
  }
};

}  // namespace ocp::testing
