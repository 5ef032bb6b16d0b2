#pragma once
// Test-side stand-ins for the Streamer end of the vehicle API:
//   FakeStreamer    — a minimal framed server over any ByteStream (pipe or TCP): sends control
//                     messages (append_frame + codec, real MACs), records every response with
//                     its arrival time, oversized frames and decode errors.
//   RecordingStream — a ByteStream the test drives by hand: deliver() calls on_bytes
//                     synchronously and writes are recorded, so a test can see what the client
//                     wrote *during* one on_bytes call.
#include <gtest/gtest.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ocp/byte_stream.hpp"
#include "ocp/executor.hpp"
#include "ocp/frame.hpp"
#include "ocp/json_codec.hpp"
#include "ocp/mac.hpp"
#include "ocp/messages.hpp"

namespace ocp::testing {

inline std::string control_frame(const OcpControlMessage& message) {
  std::string payload;
  encode_control_message(message, payload);
  std::string frame;
  EXPECT_TRUE(append_frame(payload, frame).ok());
  return frame;
}

inline MacKey test_mac_key() {
  MacKey key{};
  for (std::size_t index = 0; index < key.size(); ++index) key[index] = static_cast<std::uint8_t>(index * 7 + 1);
  return key;
}

class FakeStreamer {
 public:
  struct Response {
    SimTime time;
    VehicleResponseMessage message;
    std::size_t payload_bytes = 0;
  };

  explicit FakeStreamer(Executor& executor) : executor_(executor), mac_(test_mac_key()) {}
  ~FakeStreamer() { stop_control_loop(); }

  void attach(std::shared_ptr<ByteStream> stream) {
    stream_ = std::move(stream);
    decoder_.reset();
    stream_->set_handlers(ByteStreamHandlers{
        .on_bytes = [this](std::string_view bytes) { on_bytes(bytes); },
        .on_closed = [this](const std::string& reason) {
          closed = true;
          close_reason = reason;
        },
    });
  }

  AckPair issue(std::uint64_t ack_time) { return AckPair{ack_time, mac_.compute(ack_time)}; }
  bool verify(const AckPair& pair) { return mac_.verify(pair.ack_time, pair.ack_time_mac); }

  // Sends `message` with a fresh pair (ack_time = now in µs + ack_offset) unless keep_pair.
  AckPair send_control(OcpControlMessage message, bool keep_pair = false) {
    if (!keep_pair) message.ack = issue(static_cast<std::uint64_t>(executor_.now().count()) + ack_offset);
    sent.push_back({executor_.now(), message.ack});
    send_raw(control_frame(message));
    return message.ack;
  }
  void send_raw(std::string_view bytes) {
    if (stream_) stream_->write(bytes);
  }
  void close() {
    if (stream_) stream_->close();
  }

  // Sends `templ` every `period` (absolute deadlines) with a fresh pair each time.
  void start_control_loop(Micros period = Micros{10'000}) {
    loop_ = std::make_unique<PeriodicTimer>(executor_, period, [this](SimTime) { send_control(templ); });
    loop_->start(executor_.now());
  }
  void stop_control_loop() {
    if (loop_) loop_->stop();
  }

  OcpControlMessage templ;          // what the control loop sends
  std::uint64_t ack_offset = 0;     // added to every issued ack_time
  struct Sent {
    SimTime time;
    AckPair ack;
  };
  std::vector<Sent> sent;
  std::vector<Response> responses;
  std::vector<std::uint32_t> oversized_lengths;
  std::vector<std::string> decode_errors;
  std::uint64_t bytes_received = 0;
  bool closed = false;
  std::string close_reason;

 private:
  void on_bytes(std::string_view bytes) {
    bytes_received += bytes.size();
    while (!bytes.empty()) {
      FrameEvent event;
      bytes.remove_prefix(decoder_.put(bytes, event));
      if (event.kind == FrameEvent::Kind::frame) {
        Result<VehicleResponseMessage> message = decode_vehicle_response(event.payload);
        if (message.ok()) {
          responses.push_back({executor_.now(), *message, event.payload.size()});
        } else {
          decode_errors.push_back(message.error().message());
        }
      } else if (event.kind == FrameEvent::Kind::oversized_dropped) {
        oversized_lengths.push_back(event.declared_length);
      }
    }
  }

  Executor& executor_;
  AckMac mac_;
  std::shared_ptr<ByteStream> stream_;
  FrameDecoder decoder_;
  std::unique_ptr<PeriodicTimer> loop_;
};

class RecordingStream final : public ByteStream {
 public:
  void set_handlers(ByteStreamHandlers handlers) override { handlers_ = std::move(handlers); }
  void write(std::string_view bytes) override {
    if (open_) written += bytes;
  }
  void close() override { open_ = false; }
  bool is_open() const override { return open_; }
  std::string peer_name() const override { return "recording"; }
  void set_no_delay(bool enabled) override { no_delay = enabled; }

  void deliver(std::string_view bytes) { handlers_.on_bytes(bytes); }
  void peer_close(const std::string& reason) {
    open_ = false;
    handlers_.on_closed(reason);
  }
  // Decodes every complete response written so far.
  std::vector<VehicleResponseMessage> responses() const {
    std::vector<VehicleResponseMessage> result;
    FrameDecoder decoder;
    std::string_view rest = written;
    while (!rest.empty()) {
      FrameEvent event;
      rest.remove_prefix(decoder.put(rest, event));
      if (event.kind == FrameEvent::Kind::frame) {
        Result<VehicleResponseMessage> message = decode_vehicle_response(event.payload);
        if (message.ok()) result.push_back(*message);
      }
    }
    return result;
  }

  std::string written;
  bool no_delay = false;

 private:
  ByteStreamHandlers handlers_;
  bool open_ = true;
};

}  // namespace ocp::testing
