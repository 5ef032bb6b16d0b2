#pragma once
// The operator-side TCP client (`tcp` source, SPEC §4.2) over any ByteStream: framed
// ClientOcpShared in, framed VehicleOcpShared out, with the §2 rules — oversized inbound
// frames drained and the connection kept; malformed JSON, wrong types, missing fields and EOF
// inside a frame close it with the reason logged; no byte for `read_timeout` closes it.
//
// Lifetime: owned through a shared_ptr; stream and timer callbacks hold only weak pointers,
// so the owner may drop it from inside one of its own callbacks.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "ocp/byte_stream.hpp"
#include "ocp/executor.hpp"
#include "ocp/frame.hpp"
#include "ocp/log.hpp"
#include "ocp/messages.hpp"
#include "player/player_core.hpp"

namespace ocp {

class OperatorClientConnection : public std::enable_shared_from_this<OperatorClientConnection> {
 public:
  struct Callbacks {
    std::function<void(ClientOcpShared&&)> on_message;
    // Called once when the connection ends for any reason (peer, error, timeout, close()).
    std::function<void(const std::string& reason)> on_closed;
  };

  OperatorClientConnection(Executor& executor, std::shared_ptr<ByteStream> stream,
                           Micros read_timeout, Logger logger, PlayerStats& stats,
                           Callbacks callbacks);
  ~OperatorClientConnection();
  OperatorClientConnection(const OperatorClientConnection&) = delete;
  OperatorClientConnection& operator=(const OperatorClientConnection&) = delete;

  // Installs the stream handlers and arms the read timeout. Call once, after construction.
  void start();
  // Encodes and sends one framed VehicleOcpShared. Never sends an oversized frame.
  void send(const VehicleOcpShared& shared);
  void close(const std::string& reason);

  bool open() const { return open_; }
  const std::string& peer_name() const { return peer_name_; }

 private:
  void on_bytes(std::string_view bytes);
  void on_peer_closed(const std::string& reason);
  void arm_read_timer();
  void on_read_timer();
  void finish(const std::string& reason);

  Executor& executor_;
  std::shared_ptr<ByteStream> stream_;
  Micros read_timeout_;
  Logger logger_;
  PlayerStats& stats_;
  Callbacks callbacks_;
  std::string peer_name_;
  FrameDecoder decoder_;
  SimTime last_byte_at_{0};
  Executor::TimerId read_timer_ = 0;
  bool timer_armed_ = false;
  bool open_ = false;
  bool warned_too_large_ = false;
  std::string json_buffer_;
  std::string frame_buffer_;
};

}  // namespace ocp
