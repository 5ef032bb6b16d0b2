#pragma once
// The Streamer end of the vehicle API (SPEC §3) as a test peer, for testing vehicle clients:
// sends control messages with real MACs (once, or every period on absolute deadlines) and
// records every response with its arrival time, and every frame that is no response.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "framed_peer.hpp"
#include "ocp/executor.hpp"
#include "ocp/json_codec.hpp"
#include "ocp/mac.hpp"
#include "ocp/messages.hpp"

namespace ocp::testing {

inline std::string control_frame(const OcpControlMessage& message) {
  std::string payload;
  encode_control_message(message, payload);
  return frame_of(payload);
}

// A fixed key, so a test can compute the MAC of any ack_time itself.
inline MacKey test_mac_key() {
  MacKey key{};
  for (std::size_t index = 0; index < key.size(); ++index) key[index] = static_cast<std::uint8_t>(index * 7 + 1);
  return key;
}

class StreamerPeer : public FramedPeer {
 public:
  struct Response {
    SimTime time;
    VehicleResponseMessage message;
    std::size_t payload_bytes = 0;
  };
  struct Sent {
    SimTime time;
    AckPair ack;
  };

  explicit StreamerPeer(Executor& executor) : FramedPeer(&executor), executor_(executor), mac_(test_mac_key()) {}
  ~StreamerPeer() override { stop_control_loop(); }

  AckPair issue(std::uint64_t ack_time) { return AckPair{ack_time, mac_.compute(ack_time)}; }
  bool verify(const AckPair& pair) { return mac_.verify(pair.ack_time, pair.ack_time_mac); }

  // Sends `message` with a fresh pair (ack_time = now in µs + ack_offset) unless keep_pair.
  AckPair send_control(OcpControlMessage message, bool keep_pair = false) {
    if (!keep_pair) message.ack = issue(static_cast<std::uint64_t>(executor_.now().count()) + ack_offset);
    sent.push_back({executor_.now(), message.ack});
    send_raw(control_frame(message));
    return message.ack;
  }

  // Sends `templ` every `period` (absolute deadlines) with a fresh pair each time.
  void start_control_loop(Micros period = Micros{10'000}) {
    loop_ = std::make_unique<PeriodicTimer>(executor_, period, [this](SimTime) { send_control(templ); });
    loop_->start(executor_.now());
  }
  void stop_control_loop() {
    if (loop_) loop_->stop();
  }

  OcpControlMessage templ;       // what the control loop sends
  std::uint64_t ack_offset = 0;  // added to every issued ack_time
  std::vector<Sent> sent;
  std::vector<Response> responses;
  std::vector<std::string> decode_errors;

 protected:
  void handle_frame(const ReceivedFrame& frame) override {
    Result<VehicleResponseMessage> message = decode_vehicle_response(frame.payload);
    if (message.ok()) {
      responses.push_back({frame.at, *message, frame.payload.size()});
    } else {
      decode_errors.push_back(message.error().message());
    }
  }

 private:
  Executor& executor_;
  AckMac mac_;
  std::unique_ptr<PeriodicTimer> loop_;
};

}  // namespace ocp::testing
