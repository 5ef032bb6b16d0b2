#pragma once
// One end of a duplex byte connection. Two interchangeable implementations: an in-memory
// pipe (either time; pipe.hpp) and a TCP socket (real time; tcp_stream.hpp). The reference
// vehicle client and the Streamer's connection handling run over either unchanged.
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

namespace ocp {

struct ByteStreamHandlers {
  // Bytes arrived, in order, in arbitrary chunks. The view is valid only during the call.
  std::function<void(std::string_view bytes)> on_bytes;
  // The peer closed, or the transport failed. Not called for a local close().
  std::function<void(const std::string& reason)> on_closed;
};

class ByteStream {
 public:
  virtual ~ByteStream() = default;
  // Reading starts when handlers are first set, so no bytes are lost before that.
  virtual void set_handlers(ByteStreamHandlers handlers) = 0;
  // Queues bytes for sending; never blocks. Ignored after close.
  virtual void write(std::string_view bytes) = 0;
  // Closes both directions; the peer sees on_closed.
  virtual void close() = 0;
  virtual bool is_open() const = 0;
  // Human-readable peer name for logs: "127.0.0.1:53122" or "pipe:truck-1".
  virtual std::string peer_name() const = 0;
  // Optional TCP_NODELAY etc.; no-op for pipes.
  virtual void set_no_delay(bool) {}
  // Bytes accepted by write() that the peer has not taken yet (still in our queue; for a pipe,
  // also those the peer has not read). A writer that limits its queue checks this: it is how
  // a peer that stopped reading is detected before it can grow our memory.
  virtual std::size_t queued_bytes() const { return 0; }
  // The peer has already closed (or reset) the connection, but that is not delivered yet: its
  // close still waits behind bytes not read, or the event loop has not run since (a process
  // that was stopped, then resumed, finds it so). A server taking one connection at a time
  // asks before it refuses a newcomer for the sake of this one.
  virtual bool peer_hung_up() const { return false; }
};

}  // namespace ocp
