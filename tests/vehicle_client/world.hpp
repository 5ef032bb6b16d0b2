#pragma once
// A vehicle client and a StreamerPeer joined by an in-memory pipe, in virtual time.
#include <memory>
#include <string>
#include <vector>

#include "inputs.hpp"
#include "ocp/log.hpp"
#include "ocp/pipe.hpp"
#include "ocp/virtual_executor.hpp"
#include "streamer_peer.hpp"
#include "vehicle_client/vehicle_client.hpp"

namespace ocp::testing {

struct ClientWorld {
  explicit ClientWorld(VehicleClientConfig client_config = {}, PipeOptions pipe_options = {})
      : config(std::move(client_config)) {
    client = std::make_unique<VehicleClient>(executor, config, Logger(executor, "vehicle-client", make_null_sink()));
    client->set_on_disconnected([this](const std::string& reason) { disconnects.push_back(reason); });
    connect(pipe_options);
  }

  // A fresh pipe and a fresh streamer, as after a reconnect.
  void connect(PipeOptions pipe_options = {}) {
    streamer = std::make_unique<StreamerPeer>(executor);
    pipe = make_pipe(executor, pipe_options);
    streamer->attach(pipe.a);
    client->attach(pipe.b);
  }

  VirtualExecutor executor;
  VehicleClientConfig config;
  std::unique_ptr<VehicleClient> client;
  std::unique_ptr<StreamerPeer> streamer;
  PipeEnds pipe;
  std::vector<std::string> disconnects;
};

// Largest gap between consecutive responses (and from `from` to the first one).
inline Micros largest_response_gap(const std::vector<StreamerPeer::Response>& responses, SimTime from) {
  Micros largest{0};
  SimTime previous = from;
  for (const auto& response : responses) {
    largest = std::max(largest, response.time - previous);
    previous = response.time;
  }
  return largest;
}

}  // namespace ocp::testing
