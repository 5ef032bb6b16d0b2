// One framed JSON connection with the SPEC §2 rules (see framed_connection.hpp).
#include "ocp/framed_connection.hpp"

#include <system_error>
#include <utility>

#include <fmt/format.h>

namespace ocp {
namespace {

void add(std::uint64_t* counter, std::uint64_t amount) {
  if (counter != nullptr) *counter += amount;
}

}  // namespace

std::shared_ptr<FramedConnection> FramedConnection::open(Executor& executor, Logger logger,
                                                         std::shared_ptr<ByteStream> stream,
                                                         Options options, Counters counters,
                                                         Handlers handlers) {
  std::shared_ptr<FramedConnection> connection(
      new FramedConnection(executor, std::move(logger), std::move(stream), std::move(options),
                           counters, std::move(handlers)));
  connection->start();
  return connection;
}

FramedConnection::FramedConnection(Executor& executor, Logger logger,
                                   std::shared_ptr<ByteStream> stream, Options options,
                                   Counters counters, Handlers handlers)
    : executor_(executor),
      logger_(std::move(logger)),
      stream_(std::move(stream)),
      peer_(stream_->peer_name()),
      options_(std::move(options)),
      counters_(counters),
      handlers_(std::move(handlers)),
      decoder_(options_.payload_limit_bytes) {}

FramedConnection::~FramedConnection() {
  if (read_timer_ != 0) executor_.cancel(read_timer_);
  if (stream_->is_open()) stream_->close();
}

void FramedConnection::start() {
  std::weak_ptr<FramedConnection> weak = weak_from_this();
  if (!stream_->is_open()) {
    // Closed locally before we got it: no on_closed will ever come from the stream. Report it
    // from the executor so the owner has stored its pointer by then.
    executor_.post([weak] {
      if (auto self = weak.lock()) self->close("stream already closed");
    });
    return;
  }
  last_byte_at_ = executor_.now();
  if (options_.read_timeout.count() > 0) arm_read_timer(last_byte_at_ + options_.read_timeout);
  stream_->set_no_delay(true);
  stream_->set_handlers(ByteStreamHandlers{
      [weak](std::string_view bytes) {
        if (auto self = weak.lock()) self->handle_bytes(bytes);
      },
      [weak](const std::string& reason) {
        if (auto self = weak.lock()) self->handle_peer_closed(reason);
      }});
}

Status FramedConnection::send(std::string_view payload) {
  if (!open_) {
    return Error{std::make_error_code(std::errc::not_connected),
                 fmt::format("{} connection {} is closed", options_.label, peer_)};
  }
  frame_buffer_.clear();
  Status framed = append_frame(payload, frame_buffer_, options_.payload_limit_bytes);
  if (!framed) return framed;  // never send an oversized frame (SPEC §2)
  add(counters_.bytes_out, frame_buffer_.size());
  stream_->write(frame_buffer_);
  return framed;
}

void FramedConnection::handle_bytes(std::string_view bytes) {
  if (!open_ || bytes.empty()) return;
  add(counters_.bytes_in, bytes.size());
  last_byte_at_ = executor_.now();
  if (auto diagnosis = sniffer_.observe(bytes)) {
    logger_.warn("{} {}: {}", options_.label, peer_, *diagnosis);
  }
  // The decoder never buffers more than one payload (≤ the limit) and drains oversized
  // frames, so a hostile peer cannot grow memory here whatever it sends.
  while (!bytes.empty() && open_) {
    FrameEvent event;
    const std::size_t consumed = decoder_.put(bytes, event);
    bytes.remove_prefix(consumed);
    switch (event.kind) {
      case FrameEvent::Kind::frame:
        handle_payload(event.payload);
        break;
      case FrameEvent::Kind::oversized_dropped:
        add(counters_.oversized_frames_dropped, 1);
        logger_.warn("{} {}: dropped oversized frame of {} bytes (limit {}); connection kept",
                     options_.label, peer_, event.declared_length, options_.payload_limit_bytes);
        break;
      case FrameEvent::Kind::need_more:
        if (consumed == 0) return;  // defensive: the decoder promised to consume everything
        break;
    }
  }
}

void FramedConnection::handle_payload(std::string_view payload) {
  if (!handlers_.on_payload) return;
  const Status handled = handlers_.on_payload(payload);
  if (!handled) close(handled.error().message());
}

void FramedConnection::handle_peer_closed(const std::string& transport_reason) {
  if (!open_) return;
  const Status end = decoder_.finish();
  if (!end) {
    logger_.warn("{} {}: stream ended inside a frame ({}): {}", options_.label, peer_,
                 transport_reason, end.error().message());
    finish(end.error().message());
    return;
  }
  logger_.info("{} {}: peer closed the connection ({})", options_.label, peer_, transport_reason);
  finish("peer closed: " + transport_reason);
}

void FramedConnection::arm_read_timer(SimTime deadline) {
  read_timer_ = executor_.call_at(deadline, [weak = weak_from_this()] {
    if (auto self = weak.lock()) self->on_read_timer();
  });
}

void FramedConnection::on_read_timer() {
  read_timer_ = 0;
  if (!open_) return;
  // One timer per connection, moved forward lazily: bytes only update last_byte_at_, so a
  // flood of tiny frames costs no timer churn.
  const SimTime deadline = last_byte_at_ + options_.read_timeout;
  if (executor_.now() < deadline) {
    arm_read_timer(deadline);
    return;
  }
  close(fmt::format("read timeout: no data from the {} for {} ms", options_.label,
                    to_whole_ms(options_.read_timeout)));
}

void FramedConnection::close(const std::string& reason) {
  if (!open_) return;
  logger_.warn("closing {} connection {}: {}", options_.label, peer_, reason);
  finish(reason);
}

void FramedConnection::finish(const std::string& plain_reason) {
  if (!open_) return;
  const std::string reason =
      sniffer_.diagnosis() ? plain_reason + "; " + *sniffer_.diagnosis() : plain_reason;
  // The owner usually drops its reference inside on_closed; stay alive until we return.
  const auto self = shared_from_this();
  open_ = false;
  if (read_timer_ != 0) {
    executor_.cancel(read_timer_);
    read_timer_ = 0;
  }
  if (stream_->is_open()) stream_->close();
  if (handlers_.on_closed) handlers_.on_closed(reason);
}

}  // namespace ocp
