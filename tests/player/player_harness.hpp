#pragma once
// Test harness for PlayerCore in virtual time: links with zero impairments whose receivers
// record what the Player sends, helpers to feed Streamer messages, a captured log, and an
// operator TCP client over an in-memory pipe that speaks the real framing + codec.
#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "ocp/com_channel.hpp"
#include "ocp/frame.hpp"
#include "ocp/json_codec.hpp"
#include "ocp/log.hpp"
#include "ocp/pipe.hpp"
#include "ocp/virtual_executor.hpp"
#include "player/player_core.hpp"

namespace ocp::testing {

inline SimTime at_ms(std::int64_t ms) { return SimTime{ms * 1000}; }

struct CapturedLog {
  SimTime time;
  LogLevel level;
  std::string component;
  std::string message;
};

struct Sent {
  SimTime time;
  LinkMessage message;
};

class PlayerHarness {
 public:
  explicit PlayerHarness(PlayerConfig config = {})
      : player(executor, std::move(config),
               Logger(executor, "player", [this](const LogRecord& record) {
                 logs.push_back({record.time, record.level, std::string(record.component),
                                 std::string(record.message)});
               })) {}

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

  bool logged(LogLevel level, const std::string& needle) const {
    for (const CapturedLog& log : logs) {
      if (log.level == level && log.message.find(needle) != std::string::npos) return true;
    }
    return false;
  }
  const CapturedLog* find_log(LogLevel level, const std::string& needle) const {
    for (const CapturedLog& log : logs) {
      if (log.level == level && log.message.find(needle) != std::string::npos) return &log;
    }
    return nullptr;
  }

  VirtualExecutor executor;
  std::vector<CapturedLog> logs;
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

// An operator-side TCP client attached through an in-memory pipe; it speaks exactly what a
// TCP client on :4001 speaks (length-prefixed JSON through the libocp codec).
class TestOperatorClient {
 public:
  TestOperatorClient(PlayerHarness& harness, std::string name = "pipe:operator-1",
                     std::size_t max_chunk_bytes = 0)
      : harness_(harness) {
    PipeOptions options;
    options.name_b = std::move(name);  // the Player's end sees this peer name
    options.max_chunk_bytes = max_chunk_bytes;
    PipeEnds ends = make_pipe(harness.executor, options);
    end_ = ends.b;
    ByteStreamHandlers handlers;
    handlers.on_bytes = [this](std::string_view bytes) { on_bytes(bytes); };
    handlers.on_closed = [this](const std::string& reason) {
      closed = true;
      closed_at = harness_.executor.now();
      close_reason = reason;
    };
    end_->set_handlers(std::move(handlers));
    harness.player.accept_client_connection(ends.a);
  }

  void send(const ClientOcpShared& data) {
    std::string json;
    encode_client_ocp_shared(data, json);
    send_payload(json);
  }
  void send_payload(std::string_view payload) {
    std::string framed;
    ASSERT_TRUE(append_frame(payload, framed, 1u << 30).ok());
    end_->write(framed);
  }
  void write_raw(std::string_view bytes) { end_->write(bytes); }
  void close() { end_->close(); }
  bool open() const { return end_->is_open(); }

  std::vector<VehicleOcpShared> received;
  std::vector<SimTime> received_at;
  std::size_t decode_errors = 0;
  bool closed = false;
  SimTime closed_at{-1};
  std::string close_reason;

 private:
  void on_bytes(std::string_view bytes) {
    while (!bytes.empty()) {
      FrameEvent event;
      const std::size_t consumed = decoder_.put(bytes, event);
      if (event.kind == FrameEvent::Kind::frame) {
        auto decoded = decode_vehicle_ocp_shared(event.payload);
        if (decoded) {
          received.push_back(std::move(decoded).value());
          received_at.push_back(harness_.executor.now());
        } else {
          ++decode_errors;
        }
      }
      bytes.remove_prefix(consumed);
      if (consumed == 0) break;
    }
  }

  PlayerHarness& harness_;
  std::shared_ptr<ByteStream> end_;
  FrameDecoder decoder_;
};

}  // namespace ocp::testing
