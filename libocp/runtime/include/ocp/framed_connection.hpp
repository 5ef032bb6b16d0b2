#pragma once
// One framed JSON connection over any ByteStream (pipe or TCP), with the SPEC §2 rules shared
// by both TCP APIs (Streamer ↔ vehicle on :4000, Player ↔ client on :4001):
//   * frames are deframed; each complete payload goes to `on_payload`, which decodes and
//     dispatches it and returns an Error to close the connection with that reason (malformed
//     JSON, not an object, a missing or mistyped field);
//   * an inbound frame over the limit is drained, counted and logged (the first of a run in
//     full, the rest counted: a line every 5 s and one at the close); the connection is kept;
//   * the stream ending inside a frame closes it with the decoder's truncated_frame reason;
//   * no byte for `read_timeout` (between frames as well as inside one) closes it;
//   * `send` frames an already-encoded payload and refuses (LocalError::frame_too_large) to
//     send one over the limit — an oversized frame never leaves;
//   * a peer that stops reading is disconnected (PeerError::not_reading, "peer not reading")
//     when bytes have waited for it for write_stall_timeout without any of them being taken
//     (10 s on both ports: one rule, whatever a port's byte rate), or once the bytes queued
//     for it would exceed write_queue_limit_bytes (16 MiB, more than 10 s of the largest
//     frames at 100 Hz): it can never grow our memory beyond that. Both are checked when a
//     frame is sent (every 10 ms on :4000, every Player frame on :4001).
// Every close path — peer, timeout, bad input, write queue, local close() — reports
// `on_closed` exactly once with a typed CloseReason (a PeerError or LocalError value and its
// detail) and is logged with it. When the first bytes of the connection are not OCP framing at
// all (text, HTTP; framing_diagnosis.hpp) a warning says so at once and every later close
// reason repeats it in its detail; the bytes are still drained as SPEC §2 asks.
//
// Events: with Options::events set, every frame in and out is published as a WireFrame (with
// the ack pair a vehicle-wire message carries: given by the caller — send(payload, pair),
// note_inbound_pair() — or else decoded, only while somebody listens), and the connection's
// open and close as ConnectionEvents. An inbound frame is published right after its handler
// ran, before a close that its content causes. A WireFrame's time is when its bytes met the
// socket: an outbound frame's is taken just before the write is issued, an inbound frame's
// when the read that carried it returned (before it was decoded and handled) — so a frame
// out → response in interval is the round trip a bare socket echo measures (ocp_bench loop).
//
// Lifetime: open() returns the only shared_ptr the owner needs. Stream and timer callbacks
// hold weak pointers and lock them for the duration of a callback, so the owner may drop the
// connection from inside on_payload or on_closed. Destroying it closes the stream without
// reporting on_closed.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "ocp/byte_stream.hpp"
#include "ocp/error.hpp"
#include "ocp/event_bus.hpp"
#include "ocp/executor.hpp"
#include "ocp/frame.hpp"
#include "ocp/framing_diagnosis.hpp"
#include "ocp/log.hpp"
#include "ocp/log_limiter.hpp"

namespace ocp {

// A peer that has taken none of the bytes waiting for it for this long is not reading.
inline constexpr Micros default_write_stall_timeout{10'000'000};
// 16 MiB: 10 s of the largest frames (16 KiB) at both ports' highest rate (100 a second), so
// that at the product's rates the 10 s rule drops a deaf peer, not this memory bound.
inline constexpr std::size_t default_write_queue_limit_bytes = 16 * 1024 * 1024;

class FramedConnection : public std::enable_shared_from_this<FramedConnection> {
 public:
  struct Options {
    // Who the peer is ("vehicle", "tcp client"): starts every log line and the timeout reason.
    std::string label = "peer";
    // No byte for this long closes the connection; zero (or negative) disables the rule.
    Micros read_timeout{2'000'000};
    std::size_t payload_limit_bytes = max_payload_bytes;
    // Bytes we may have queued for a peer that is not reading before we disconnect it.
    std::size_t write_queue_limit_bytes = default_write_queue_limit_bytes;
    // How long bytes may wait for a peer that takes none of them; zero (or negative) disables.
    Micros write_stall_timeout = default_write_stall_timeout;
    // Where frame and connection events go (nullptr: none), and how they are labelled.
    EventBus* events = nullptr;
    Component component{};
    Wire wire = Wire::vehicle;
    WireMessageKind inbound_kind = WireMessageKind::vehicle_response;
    WireMessageKind outbound_kind = WireMessageKind::control;
    // Shared by a server's connections (nullptr: every line written): see log_limiter.hpp.
    ConnectionLogBudget* log_budget = nullptr;
  };

  // Where the connection adds what it counts. Each member points into the owner's stats, so
  // the owner's numbers stay live and add up across connections; the owner's stats must
  // outlive the connection. Null members are not counted.
  struct Counters {
    std::uint64_t* bytes_in = nullptr;                  // every byte received
    std::uint64_t* bytes_out = nullptr;                 // every byte written (headers included)
    std::uint64_t* oversized_frames_dropped = nullptr;  // inbound frames drained
  };

  struct Handlers {
    // Decodes and dispatches one complete payload (valid only during the call). An error
    // closes the connection with that error as the reason.
    std::function<Status(std::string_view payload)> on_payload;
    // Called exactly once, whatever closed the connection.
    std::function<void(const CloseReason& reason)> on_closed;
  };

  // The options of a server's end of `wire`, built only here: the Streamer's vehicle
  // connection (Wire::vehicle, peer "vehicle": control out, VehicleResponse in) and the
  // Player's tcp client (Wire::operator_, peer "tcp client": VehicleOcpShared out,
  // ClientOcpShared in). Events go to `events` as `component`; the rest keeps its defaults.
  [[nodiscard]] static Options server_options(Wire wire, Micros read_timeout, EventBus& events,
                                              Component component);

  // Takes over `stream`, starts reading from it and arms the read timeout. A stream that is
  // already closed is reported through on_closed from the executor, never from inside open().
  [[nodiscard]] static std::shared_ptr<FramedConnection> open(Executor& executor, Logger logger,
                                                              std::shared_ptr<ByteStream> stream,
                                                              Options options, Counters counters,
                                                              Handlers handlers);
  ~FramedConnection();
  FramedConnection(const FramedConnection&) = delete;
  FramedConnection& operator=(const FramedConnection&) = delete;

  // Frames and writes one encoded payload. Fails with LocalError::frame_too_large (nothing
  // written) when the payload is over the limit, and with LocalError::not_connected once the
  // connection is closed. A peer whose queue would overflow is disconnected (not_reading) and
  // the send fails with that reason.
  // `carried`: the ack pair the payload carries, when the caller knows it — saves decoding the
  // payload again for the WireFrame event while somebody listens.
  [[nodiscard]] Status send(std::string_view payload, std::optional<AckPair> carried = std::nullopt);
  // Writes `bytes` exactly as given — no framing, no size check — under the same write-queue
  // rule as send(). For the conformance suite, which must be able to put an oversized or
  // hand-cut frame on the wire; protocol code always uses send(). Publishes no WireFrame (the
  // caller knows what the bytes mean and publishes one if it wants).
  [[nodiscard]] Status write_raw(std::string_view bytes);
  // Called from inside on_payload by a handler that decoded the ack pair the payload carries:
  // the inbound WireFrame event (published right after on_payload returns) reuses it instead
  // of decoding the payload a second time.
  void note_inbound_pair(const AckPair& pair) { inbound_pair_ = pair; }
  // Closes with `reason` (logged as a warning; our own shut_down as info), closes the stream,
  // reports on_closed.
  void close(CloseReason reason);

  bool is_open() const { return open_; }
  // Open here, but the peer has hung up already (ByteStream::peer_hung_up): its close has not
  // been read yet. A one-connection server closes it rather than refuse a newcomer for it.
  bool peer_hung_up() const { return open_ && stream_->peer_hung_up(); }
  const std::string& peer() const { return peer_; }

 private:
  bool may_log() const;   // the server's ConnectionLogBudget admits a line (or there is none)
  FramedConnection(Executor& executor, Logger logger, std::shared_ptr<ByteStream> stream,
                   Options options, Counters counters, Handlers handlers);
  void start();
  void handle_bytes(std::string_view bytes);
  void handle_payload(std::string_view payload);
  void handle_peer_closed(const std::string& transport_reason);
  void warn_oversized(std::uint32_t declared_length);
  void say_oversized(const RepeatedWarning::Summary& summary);
  void arm_read_timer(SimTime deadline);
  void on_read_timer();
  void finish(const CloseReason& reason);
  // The write-queue rules of send() and write_raw(): Ok when the peer took something within
  // write_stall_timeout and `bytes` more fit the queue, else the peer is not reading — the
  // connection is closed and the returned reason says so.
  Status admit_to_write_queue(std::size_t bytes);
  void publish_frame(SimTime at, FrameDirection direction, WireMessageKind kind, std::uint32_t length_prefix,
                     std::string_view payload, bool drained, std::optional<AckPair> carried = std::nullopt);
  void publish_connection(ConnectionChange change, const CloseReason* reason);

  Executor& executor_;
  Logger logger_;
  std::shared_ptr<ByteStream> stream_;
  std::string peer_;
  Options options_;
  Counters counters_;
  Handlers handlers_;
  FrameDecoder decoder_;
  FramingSniffer sniffer_;    // says so when the peer does not speak OCP framing at all
  std::string frame_buffer_;  // reused by send(): no allocation per frame in steady state
  bool open_ = true;
  SimTime last_byte_at_{};    // when the latest read returned: the time of the frames it carried
  std::optional<AckPair> inbound_pair_;   // set by the handler of the payload being handled
  Executor::TimerId read_timer_ = 0;
  // The write-stall rule: bytes ever written, what the peer had taken at the last send, and
  // since when it has taken nothing while bytes waited (admit_to_write_queue).
  std::uint64_t written_ = 0, taken_ = 0;
  SimTime taking_nothing_since_{};
  RepeatedWarning oversized_warnings_;   // "dropped oversized frame": once, then counted
};

}  // namespace ocp
