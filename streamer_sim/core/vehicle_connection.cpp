#include "vehicle_connection.hpp"

#include <fmt/format.h>

#include "ocp/json_codec.hpp"

namespace ocp::streamer {

std::shared_ptr<VehicleConnection> VehicleConnection::open(Executor& executor,
                                                           const Logger& logger,
                                                           std::shared_ptr<ByteStream> stream,
                                                           Micros read_timeout,
                                                           StreamerStats& stats, Events events) {
  std::shared_ptr<VehicleConnection> connection(new VehicleConnection(
      executor, logger, std::move(stream), read_timeout, stats, std::move(events)));
  connection->start_reading();
  return connection;
}

VehicleConnection::VehicleConnection(Executor& executor, const Logger& logger,
                                     std::shared_ptr<ByteStream> stream, Micros read_timeout,
                                     StreamerStats& stats, Events events)
    : executor_(executor),
      logger_(logger),
      stream_(std::move(stream)),
      peer_(stream_->peer_name()),
      read_timeout_(read_timeout),
      stats_(stats),
      events_(std::move(events)) {}

VehicleConnection::~VehicleConnection() {
  if (read_timer_ != 0) executor_.cancel(read_timer_);
  if (stream_ && stream_->is_open()) stream_->close();
}

void VehicleConnection::start_reading() {
  last_byte_at_ = executor_.now();
  arm_read_timer(last_byte_at_ + read_timeout_);
  std::weak_ptr<VehicleConnection> weak = weak_from_this();
  stream_->set_no_delay(true);
  stream_->set_handlers(ByteStreamHandlers{
      [weak](std::string_view bytes) {
        if (auto self = weak.lock()) self->handle_bytes(bytes);
      },
      [weak](const std::string& reason) {
        if (auto self = weak.lock()) self->handle_peer_closed(reason);
      }});
}

void VehicleConnection::write(std::string_view framed_bytes) {
  if (!open_) return;
  stats_.vehicle_bytes_out += framed_bytes.size();
  stream_->write(framed_bytes);
}

void VehicleConnection::handle_bytes(std::string_view bytes) {
  if (!open_ || bytes.empty()) return;
  stats_.vehicle_bytes_in += bytes.size();
  last_byte_at_ = executor_.now();
  // The decoder never buffers more than one payload (≤ 16 KiB) and drains oversized frames,
  // so a hostile peer cannot grow memory here whatever it sends.
  while (!bytes.empty() && open_) {
    FrameEvent event;
    const std::size_t consumed = decoder_.put(bytes, event);
    bytes.remove_prefix(consumed);
    switch (event.kind) {
      case FrameEvent::Kind::frame:
        handle_frame(event.payload);
        break;
      case FrameEvent::Kind::oversized_dropped:
        ++stats_.oversized_frames_dropped;
        logger_.warn("vehicle {}: dropped oversized frame of {} bytes (limit {}); connection kept",
                     peer_, event.declared_length, max_payload_bytes);
        break;
      case FrameEvent::Kind::need_more:
        if (consumed == 0) return;  // defensive: the decoder promised to consume everything
        break;
    }
  }
}

void VehicleConnection::handle_frame(std::string_view payload) {
  auto response = decode_vehicle_response(payload);
  if (!response) {
    close(response.error().message());
    return;
  }
  ++stats_.vehicle_responses_received;
  if (events_.on_response) events_.on_response(*response);
}

void VehicleConnection::handle_peer_closed(const std::string& transport_reason) {
  if (!open_) return;
  const Status end = decoder_.finish();
  if (!end) {
    logger_.warn("vehicle {}: connection ended inside a frame: {}", peer_, end.error().message());
    finish(end.error().message());
    return;
  }
  logger_.info("vehicle {}: peer closed the connection ({})", peer_, transport_reason);
  finish(fmt::format("peer closed: {}", transport_reason));
}

void VehicleConnection::arm_read_timer(SimTime deadline) {
  read_timer_ = executor_.call_at(deadline, [weak = weak_from_this()] {
    if (auto self = weak.lock()) self->on_read_timer();
  });
}

void VehicleConnection::on_read_timer() {
  read_timer_ = 0;
  if (!open_) return;
  // One timer per connection, moved forward lazily: bytes only update last_byte_at_, so a
  // flood of tiny frames costs no timer churn.
  const SimTime deadline = last_byte_at_ + read_timeout_;
  if (executor_.now() < deadline) {
    arm_read_timer(deadline);
    return;
  }
  close(fmt::format("read timeout: no data from the vehicle for {} ms",
                    to_whole_ms(read_timeout_)));
}

void VehicleConnection::close(const std::string& reason) {
  if (!open_) return;
  logger_.warn("closing vehicle connection {}: {}", peer_, reason);
  finish(reason);
}

void VehicleConnection::finish(const std::string& reason) {
  // The owner usually drops its reference inside on_closed; stay alive until we return.
  const auto self = shared_from_this();
  open_ = false;
  if (read_timer_ != 0) {
    executor_.cancel(read_timer_);
    read_timer_ = 0;
  }
  if (stream_->is_open()) stream_->close();
  if (events_.on_closed) events_.on_closed(reason);
}

}  // namespace ocp::streamer
