#pragma once
// An operator-side client of the Player's :4001 API (SPEC §4) as a test peer: decodes every
// VehicleOcpShared (with its arrival time) and sends ClientOcpShared. Over a pipe or TCP.
#include <functional>
#include <string>
#include <vector>

#include "framed_peer.hpp"
#include "ocp/json_codec.hpp"
#include "ocp/messages.hpp"

namespace ocp::testing {

class OperatorPeer : public FramedPeer {
 public:
  explicit OperatorPeer(const Executor* clock = nullptr) : FramedPeer(clock) {}

  void send(const ClientOcpShared& data) {
    std::string json;
    encode_client_ocp_shared(data, json);
    send_payload(json);
  }

  // Called for every object received (e.g. to echo its pairs back).
  std::function<void(const VehicleOcpShared&)> answer;

  std::vector<VehicleOcpShared> received;
  std::vector<SimTime> received_at;
  std::size_t decode_errors = 0;

  // The newest object (an empty one before any arrived).
  const VehicleOcpShared& latest() const {
    static const VehicleOcpShared none;
    return received.empty() ? none : received.back();
  }

 protected:
  void handle_frame(const ReceivedFrame& frame) override {
    auto decoded = decode_vehicle_ocp_shared(frame.payload);
    if (!decoded) {
      ++decode_errors;
      return;
    }
    received.push_back(std::move(decoded).value());
    received_at.push_back(frame.at);
    if (answer) answer(received.back());
  }
};

}  // namespace ocp::testing
