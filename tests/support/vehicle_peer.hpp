#pragma once
// The vehicle end of the vehicle API (SPEC §3) as a test peer: decodes every control message
// the Streamer sends (with its arrival time and raw payload) and can echo each pair at once,
// like the reference vehicle client. Over a pipe or TCP (tcp_peers.hpp).
#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

#include "framed_peer.hpp"
#include "ocp/json_codec.hpp"
#include "ocp/messages.hpp"

namespace ocp::testing {

class VehiclePeer : public FramedPeer {
 public:
  explicit VehiclePeer(const Executor* clock = nullptr) : FramedPeer(clock) {}

  void send_response(const VehicleResponseMessage& response) {
    std::string json;
    encode_vehicle_response(response, json);
    send_payload(json);
  }
  // The answer of a well-behaved vehicle: the pair back, with echo_user_data.
  void echo_pair(const AckPair& pair) { send_response(VehicleResponseMessage{pair, echo_user_data}); }

  bool echo = false;                              // answer every control message with its pair
  std::optional<VehicleUserData> echo_user_data;  // attached to every echo
  bool fail_on_undecodable = false;               // a frame that is no control message fails the test

  std::vector<OcpControlMessage> received;
  std::vector<SimTime> received_at;
  std::vector<std::string> raw_payloads;
  std::size_t undecodable = 0;

 protected:
  void handle_frame(const ReceivedFrame& frame) override {
    raw_payloads.push_back(frame.payload);
    auto message = decode_control_message(frame.payload);
    if (!message) {
      ++undecodable;
      if (fail_on_undecodable) ADD_FAILURE() << "undecodable control message: " << message.error().message();
      return;
    }
    received.push_back(*message);
    received_at.push_back(frame.at);
    if (echo) echo_pair(message->ack);
  }
};

}  // namespace ocp::testing
