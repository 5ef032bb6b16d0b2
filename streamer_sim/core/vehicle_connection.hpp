#pragma once
// One vehicle client connection (SPEC §2, §3): framing, response decoding, read timeout.
// Works over any ByteStream (pipe or TCP). Peer errors are values: a bad frame closes the
// connection with the codec's reason; an oversized frame is drained and the connection kept.
//
// Lifetime: the core holds the only shared_ptr. Stream callbacks hold a weak_ptr and lock it
// for the duration of a callback, so the core may drop the connection from inside one.
#include <functional>
#include <memory>
#include <string>
#include <string_view>

#include "ocp/byte_stream.hpp"
#include "ocp/executor.hpp"
#include "ocp/frame.hpp"
#include "ocp/log.hpp"
#include "ocp/messages.hpp"
#include "streamer/streamer_core.hpp"

namespace ocp::streamer {

class VehicleConnection : public std::enable_shared_from_this<VehicleConnection> {
 public:
  struct Events {
    std::function<void(const VehicleResponseMessage&)> on_response;
    // Called exactly once, whatever closed the connection (peer, timeout, bad input, close()).
    std::function<void(const std::string& reason)> on_closed;
  };

  // Takes over `stream` and starts reading from it.
  static std::shared_ptr<VehicleConnection> open(Executor& executor, const Logger& logger,
                                                 std::shared_ptr<ByteStream> stream,
                                                 Micros read_timeout, StreamerStats& stats,
                                                 Events events);
  ~VehicleConnection();
  VehicleConnection(const VehicleConnection&) = delete;
  VehicleConnection& operator=(const VehicleConnection&) = delete;

  // Writes one already-framed control message.
  void write(std::string_view framed_bytes);
  // Local close: logs `reason`, closes the stream, reports on_closed.
  void close(const std::string& reason);

  bool is_open() const { return open_; }
  const std::string& peer() const { return peer_; }

 private:
  VehicleConnection(Executor& executor, const Logger& logger, std::shared_ptr<ByteStream> stream,
                    Micros read_timeout, StreamerStats& stats, Events events);
  void start_reading();
  void handle_bytes(std::string_view bytes);
  void handle_frame(std::string_view payload);
  void handle_peer_closed(const std::string& transport_reason);
  void arm_read_timer(SimTime deadline);
  void on_read_timer();
  void finish(const std::string& reason);

  Executor& executor_;
  Logger logger_;
  std::shared_ptr<ByteStream> stream_;
  std::string peer_;
  Micros read_timeout_;
  StreamerStats& stats_;
  Events events_;
  FrameDecoder decoder_;
  bool open_ = true;
  SimTime last_byte_at_{};
  Executor::TimerId read_timer_ = 0;
};

}  // namespace ocp::streamer
