#pragma once
// The one framed test peer: the far end of any ocp::ByteStream (an in-memory pipe in virtual
// time, a TCP socket over loopback in real time). It frames what it sends and deframes what it
// receives with the libocp codec (frame.hpp) — never by hand — so a test talks exactly what a
// real client or server would, and can still break the rules on purpose (oversized frames, a
// frame in pieces, raw bytes, a truncated header).
//
// Role peers (vehicle_peer.hpp, streamer_peer.hpp, operator_peer.hpp) add the typed messages
// of one side by overriding handle_frame; tcp_peers.hpp adds real sockets.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "ocp/byte_stream.hpp"
#include "ocp/executor.hpp"
#include "ocp/frame.hpp"

namespace ocp::testing {

// One frame as it arrived: the length prefix from the wire and the payload bytes untouched.
struct ReceivedFrame {
  SimTime at;                      // the peer's clock at arrival (zero without a clock)
  std::uint32_t length_prefix = 0;
  std::string payload;
};

// Tests may send frames far over the protocol limit; the receiving side must drain them.
inline constexpr std::size_t test_send_limit_bytes = std::size_t{1} << 30;

// The frame of `payload` (header + payload) as the libocp codec writes it, any size up to 1 GiB.
inline std::string frame_of(std::string_view payload) {
  std::string frame;
  const Status status = append_frame(payload, frame, test_send_limit_bytes);
  (void)status;  // only fails above 1 GiB, which no test sends
  return frame;
}

// A bare length prefix (the codec's, with no limit checked): the header of a frame of up to
// 4 GiB that never comes, or one followed by a payload cut short or over the limit.
inline std::string length_prefix(std::uint32_t length) {
  std::string header;
  append_length_prefix(length, header);
  return header;
}

// Every complete payload in a captured byte stream, in order (what a decoder would report).
inline std::vector<std::string> payloads_of(std::string_view bytes) {
  std::vector<std::string> payloads;
  FrameDecoder decoder;
  decoder.put_all(bytes, [&payloads](std::string_view payload) {
    payloads.emplace_back(payload);
    return true;
  });
  return payloads;
}

class FramedPeer {
 public:
  // `clock` stamps arrivals and the close; without one they read zero.
  explicit FramedPeer(const Executor* clock = nullptr) : clock_(clock) {}
  virtual ~FramedPeer() { close(); }
  FramedPeer(const FramedPeer&) = delete;
  FramedPeer& operator=(const FramedPeer&) = delete;

  // Takes over one end of a connection (replacing any earlier one, as after a reconnect:
  // the decoder starts afresh, received frames are kept).
  void attach(std::shared_ptr<ByteStream> stream) {
    detach();
    stream_ = std::move(stream);
    decoder_.reset();
    closed_by_peer_ = false;
    close_reason_.clear();
    closed_at_.reset();
    // Pipe deliveries run later on the executor: they must not reach a destroyed peer.
    std::weak_ptr<bool> alive = alive_;
    stream_->set_handlers(ByteStreamHandlers{
        .on_bytes = [this, alive](std::string_view bytes) {
          if (!alive.expired()) on_bytes(bytes);
        },
        .on_closed = [this, alive](const std::string& reason) {
          if (alive.expired()) return;
          closed_by_peer_ = true;
          close_reason_ = reason;
          closed_at_ = now();
          if (on_closed) on_closed(reason);
        },
    });
  }
  bool attached() const { return stream_ != nullptr; }

  // --- sending -------------------------------------------------------------------------
  void send_payload(std::string_view payload) { send_raw(frame_of(payload)); }
  // The frame of `payload` written in writes of at most `piece_bytes` (a decoder must not
  // care where the transport splits a frame).
  void send_in_pieces(std::string_view payload, std::size_t piece_bytes) {
    const std::string frame = frame_of(payload);
    for (std::size_t at = 0; at < frame.size(); at += piece_bytes) {
      send_raw(std::string_view(frame).substr(at, piece_bytes));
    }
  }
  // Any bytes: a broken header, half a frame, garbage.
  void send_raw(std::string_view bytes) {
    if (stream_) stream_->write(bytes);
  }
  // Local close: the other end sees it; closed_by_peer() stays false.
  void close() {
    if (stream_) stream_->close();
  }
  bool is_open() const { return stream_ && stream_->is_open() && !closed_by_peer_; }

  // --- receiving -----------------------------------------------------------------------
  // Called for every frame after it was stored (e.g. to answer at once).
  std::function<void(const ReceivedFrame&)> on_frame;
  std::function<void(const std::string& reason)> on_closed;

  const std::vector<ReceivedFrame>& frames() const { return frames_; }
  void clear_frames() {
    frames_.clear();
    read_ = 0;
  }
  // The next frame not polled yet, if any.
  std::optional<ReceivedFrame> poll() {
    if (read_ == frames_.size()) return std::nullopt;
    return frames_[read_++];
  }
  // Declared lengths of the inbound frames over the limit (drained, not delivered).
  const std::vector<std::uint32_t>& oversized_lengths() const { return oversized_lengths_; }
  std::uint64_t bytes_received() const { return bytes_received_; }
  // True when the stream ends inside a frame (what a short read leaves behind).
  bool mid_frame() const { return decoder_.mid_frame(); }

  bool closed_by_peer() const { return closed_by_peer_; }
  const std::string& close_reason() const { return close_reason_; }
  std::optional<SimTime> closed_at() const { return closed_at_; }

 protected:
  // Role peers decode the payload here; the frame is already in frames().
  virtual void handle_frame(const ReceivedFrame&) {}
  SimTime now() const { return clock_ ? clock_->now() : SimTime{0}; }

 private:
  void detach() {
    if (!stream_) return;
    alive_ = std::make_shared<bool>(true);  // the old stream's handlers see a dead token
    stream_->close();
    stream_.reset();
  }
  void on_bytes(std::string_view bytes) {
    bytes_received_ += bytes.size();
    decoder_.put_all(
        bytes,
        [this](std::string_view payload) {
          // The decoder reports a frame only once its whole declared length arrived.
          frames_.push_back(
              ReceivedFrame{now(), static_cast<std::uint32_t>(payload.size()), std::string(payload)});
          // Copy: a handler may send, close or even receive more, growing frames_.
          const ReceivedFrame frame = frames_.back();
          handle_frame(frame);
          if (on_frame) on_frame(frame);
          return true;
        },
        [this](std::uint32_t declared_length) {
          oversized_lengths_.push_back(declared_length);
          return true;
        });
  }

  const Executor* clock_;
  std::shared_ptr<ByteStream> stream_;
  std::shared_ptr<bool> alive_ = std::make_shared<bool>(true);
  FrameDecoder decoder_;
  std::vector<ReceivedFrame> frames_;
  std::size_t read_ = 0;
  std::vector<std::uint32_t> oversized_lengths_;
  std::uint64_t bytes_received_ = 0;
  bool closed_by_peer_ = false;
  std::string close_reason_;
  std::optional<SimTime> closed_at_;
};

}  // namespace ocp::testing
