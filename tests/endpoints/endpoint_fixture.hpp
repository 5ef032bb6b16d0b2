#pragma once
// Shared pieces of the endpoint tests: the captured log, the TCP test peers, and an echoing
// vehicle — a TCP vehicle peer that answers every control message with its pair at once.
#include <boost/asio/io_context.hpp>

#include "captured_log.hpp"
#include "ocp/asio/executor.hpp"
#include "tcp_peers.hpp"
#include "vehicle_peer.hpp"

namespace ocp::testing {

class EchoingVehicle : public TcpTestClient<VehiclePeer> {
 public:
  explicit EchoingVehicle(boost::asio::io_context& io) : TcpTestClient<VehiclePeer>(io) { echo = true; }
};

}  // namespace ocp::testing
