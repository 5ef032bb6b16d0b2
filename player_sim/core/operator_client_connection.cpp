// The operator-side TCP client connection (SPEC §2 rules on :4001).
#include "operator_client_connection.hpp"

#include <utility>

#include "ocp/json_codec.hpp"

namespace ocp {

OperatorClientConnection::OperatorClientConnection(Executor& executor,
                                                   std::shared_ptr<ByteStream> stream,
                                                   Micros read_timeout, Logger logger,
                                                   PlayerStats& stats, Callbacks callbacks)
    : executor_(executor),
      stream_(std::move(stream)),
      read_timeout_(read_timeout),
      logger_(std::move(logger)),
      stats_(stats),
      callbacks_(std::move(callbacks)),
      peer_name_(stream_->peer_name()) {}

OperatorClientConnection::~OperatorClientConnection() {
  if (timer_armed_) executor_.cancel(read_timer_);
  if (open_) stream_->close();
}

void OperatorClientConnection::start() {
  open_ = stream_->is_open();
  if (!open_) {
    finish("stream already closed");
    return;
  }
  last_byte_at_ = executor_.now();
  stream_->set_no_delay(true);
  std::weak_ptr<OperatorClientConnection> weak = weak_from_this();
  ByteStreamHandlers handlers;
  handlers.on_bytes = [weak](std::string_view bytes) {
    if (auto self = weak.lock()) self->on_bytes(bytes);
  };
  handlers.on_closed = [weak](const std::string& reason) {
    if (auto self = weak.lock()) self->on_peer_closed(reason);
  };
  arm_read_timer();
  stream_->set_handlers(std::move(handlers));
}

void OperatorClientConnection::on_bytes(std::string_view bytes) {
  if (!open_ || bytes.empty()) return;
  auto keep_alive = shared_from_this();
  last_byte_at_ = executor_.now();
  while (!bytes.empty() && open_) {
    FrameEvent event;
    const std::size_t consumed = decoder_.put(bytes, event);
    if (event.kind == FrameEvent::Kind::frame) {
      Result<ClientOcpShared> message = decode_client_ocp_shared(event.payload);
      bytes.remove_prefix(consumed);
      if (!message) {
        close("invalid ClientOcpShared: " + message.error().message());
        return;
      }
      if (callbacks_.on_message) callbacks_.on_message(std::move(message).value());
      continue;
    }
    bytes.remove_prefix(consumed);
    if (event.kind == FrameEvent::Kind::oversized_dropped) {
      ++stats_.client_oversized_frames;
      logger_.warn("tcp client {}: dropped an oversized frame of {} bytes (limit {}); keeping the connection",
                   peer_name_, event.declared_length, max_payload_bytes);
      continue;
    }
    if (consumed == 0) break;  // need_more with nothing consumed: wait for more bytes
  }
}

void OperatorClientConnection::on_peer_closed(const std::string& reason) {
  if (!open_) return;
  auto keep_alive = shared_from_this();
  const Status at_end = decoder_.finish();
  if (!at_end) {
    logger_.warn("tcp client {}: stream ended inside a frame ({}): {}", peer_name_, reason,
                 at_end.error().message());
    finish("truncated frame: " + at_end.error().message());
    return;
  }
  logger_.info("tcp client {} disconnected: {}", peer_name_, reason);
  finish("peer closed: " + reason);
}

void OperatorClientConnection::close(const std::string& reason) {
  if (!open_) return;
  auto keep_alive = shared_from_this();
  logger_.warn("closing tcp client {}: {}", peer_name_, reason);
  stream_->close();
  finish(reason);
}

void OperatorClientConnection::finish(const std::string& reason) {
  open_ = false;
  if (timer_armed_) {
    executor_.cancel(read_timer_);
    timer_armed_ = false;
  }
  ++stats_.client_connections_closed;
  if (callbacks_.on_closed) callbacks_.on_closed(reason);
}

void OperatorClientConnection::arm_read_timer() {
  if (read_timeout_.count() <= 0) return;  // a zero timeout disables the silence rule
  std::weak_ptr<OperatorClientConnection> weak = weak_from_this();
  timer_armed_ = true;
  read_timer_ = executor_.call_at(last_byte_at_ + read_timeout_, [weak] {
    if (auto self = weak.lock()) self->on_read_timer();
  });
}

void OperatorClientConnection::on_read_timer() {
  timer_armed_ = false;
  if (!open_) return;
  // Bytes that arrived since arming moved the deadline; re-arm lazily instead of rescheduling
  // on every chunk (a flood must not flood the timer queue).
  if (executor_.now() - last_byte_at_ >= read_timeout_) {
    close("read timeout: no byte for " + std::to_string(to_whole_ms(read_timeout_)) + " ms");
    return;
  }
  arm_read_timer();
}

void OperatorClientConnection::send(const VehicleOcpShared& shared) {
  if (!open_) return;
  encode_vehicle_ocp_shared(shared, json_buffer_);
  frame_buffer_.clear();
  const Status framed = append_frame(json_buffer_, frame_buffer_);
  if (!framed) {
    // Never send an oversized frame (SPEC §2); the client simply misses this one. Logged
    // once per connection: it would otherwise repeat every frame.
    ++stats_.client_frames_too_large;
    if (warned_too_large_) return;
    warned_too_large_ = true;
    logger_.warn("tcp client {}: VehicleOcpShared not sent: {}", peer_name_, framed.error().message());
    return;
  }
  stream_->write(frame_buffer_);
  ++stats_.client_frames_sent;
}

}  // namespace ocp
