#pragma once
// The operator client stand-in of a scenario world (OperatorClientSetting, model.hpp): a small
// sans-IO peer on an in-memory pipe, attached to the Player's :4001 side the way a TCP client
// is (PlayerCore::accept_client_connection). It reads every VehicleOcpShared and sends
// ClientOcpShared keep-alives (SPEC §4.2), so the Player's feedback object is on the event
// stream (WireFrame, wire operator_); on a timeline event it misbehaves on that port
// (OperatorMisbehaviour). What the Player does about it is only seen on the event stream:
// nothing here looks into the Player.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "ocp/byte_stream.hpp"
#include "ocp/executor.hpp"
#include "ocp/frame.hpp"
#include "ocp/messages.hpp"
#include "scenario/model.hpp"
#include "world/world.hpp"

namespace ocp::scenario {

class OperatorClient {
 public:
  OperatorClient(World& world, const OperatorClientSetting& setting);
  ~OperatorClient();
  OperatorClient(const OperatorClient&) = delete;
  OperatorClient& operator=(const OperatorClient&) = delete;

  // Connects (after World::start()) and starts the keep-alives; reconnects after the Player
  // closed the connection, `reconnect_backoff` later, until stop().
  void start();
  void stop();
  // Replaces the misbehaviours from now on (SetOperatorMisbehaviour).
  void set_misbehaviour(const OperatorMisbehaviour& misbehave) { misbehave_ = misbehave; }
  // A second :4001 connection beside the client's (SPEC §4.2: refused); its far end is kept
  // open here until the client goes, so only the Player closes it.
  void open_second_connection();
  // The timeline's `client_data: {source: tcp}` in a world with this client: one
  // ClientOcpShared frame on its connection, as a TCP client sends it. False (nothing sent)
  // while it is disconnected or silent: the Player sees no tcp client data then.
  bool send_client_data(const ClientOcpShared& message);

  std::uint64_t frames_read() const { return frames_read_; }
  std::uint64_t connections() const { return connections_; }

 private:
  std::shared_ptr<ByteStream> new_connection(const std::string& name);
  void connect();
  void on_bytes(std::string_view bytes);
  void on_connection_lost();
  void on_keep_alive_tick();
  // The frame that takes the place of the keep-alive under the misbehaviours ("" = none).
  std::string next_frame() const;

  World& world_;
  OperatorClientSetting setting_;
  OperatorMisbehaviour misbehave_;
  std::shared_ptr<ByteStream> stream_;
  FrameDecoder decoder_;
  PeriodicTimer keep_alive_;
  Executor::TimerId reconnect_timer_ = 0;
  bool running_ = false;
  // Pipe deliveries run later on the executor: they must not reach a destroyed client.
  std::shared_ptr<bool> alive_ = std::make_shared<bool>(true);
  std::vector<std::shared_ptr<ByteStream>> second_connections_;   // bounded by the timeline
  std::uint64_t frames_read_ = 0;
  std::uint64_t connections_ = 0;
};

}  // namespace ocp::scenario
