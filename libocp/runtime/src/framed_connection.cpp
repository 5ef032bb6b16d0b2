// One framed JSON connection with the SPEC §2 rules (see framed_connection.hpp).
#include "ocp/framed_connection.hpp"

#include <algorithm>
#include <system_error>
#include <utility>

#include <fmt/format.h>

#include "ocp/invariant.hpp"
#include "ocp/json_codec.hpp"

namespace ocp {
namespace {

void add(std::uint64_t* counter, std::uint64_t amount) {
  if (counter != nullptr) *counter += amount;
}

// The pair a vehicle-wire message carries, for WireFrame events (only decoded while somebody
// listens). Operator-wire messages carry one pair per vehicle: none is singled out.
std::optional<AckPair> carried_pair(WireMessageKind kind, std::string_view payload) {
  switch (kind) {
    case WireMessageKind::control:
      if (auto message = decode_control_message(payload)) return message->ack;
      return std::nullopt;
    case WireMessageKind::vehicle_response:
      if (auto message = decode_vehicle_response(payload)) return message->ack;
      return std::nullopt;
    case WireMessageKind::vehicle_ocp_shared:
    case WireMessageKind::client_ocp_shared:
      return std::nullopt;
  }
  return std::nullopt;
}

}  // namespace

FramedConnection::Options FramedConnection::server_options(Wire wire, Micros read_timeout, EventBus& events,
                                                           Component component) {
  Options options;
  options.read_timeout = read_timeout;
  options.events = &events;
  options.component = component;
  options.wire = wire;
  switch (wire) {
    case Wire::vehicle:
      options.label = "vehicle";
      options.inbound_kind = WireMessageKind::vehicle_response;
      options.outbound_kind = WireMessageKind::control;
      break;
    case Wire::operator_:
      options.label = "tcp client";
      options.inbound_kind = WireMessageKind::client_ocp_shared;
      options.outbound_kind = WireMessageKind::vehicle_ocp_shared;
      break;
  }
  return options;
}

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
      if (auto self = weak.lock()) {
        self->close(CloseReason{LocalError::stream_closed, "the stream was closed before it was handed over"});
      }
    });
    return;
  }
  publish_connection(ConnectionChange::opened, nullptr);
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

Status FramedConnection::send(std::string_view payload, std::optional<AckPair> carried) {
  if (!open_) {
    return Error{LocalError::not_connected,
                 fmt::format("{} connection {} is closed", options_.label, peer_)};
  }
  frame_buffer_.clear();
  Status framed = append_frame(payload, frame_buffer_, options_.payload_limit_bytes);
  if (!framed) return framed;  // never send an oversized frame (SPEC §2)
  if (Status admitted = admit_to_write_queue(frame_buffer_.size()); !admitted) return admitted;
  OCP_INVARIANT(frame_buffer_.size() <= frame_header_bytes + max_payload_bytes,
                "no frame above 16 KiB is ever written (append_frame refuses it above)");
  add(counters_.bytes_out, frame_buffer_.size());
  const bool listening = options_.events != nullptr && options_.events->active();
  const SimTime issued_at = listening ? executor_.now() : SimTime{};   // before the write syscall
  stream_->write(frame_buffer_);
  if (listening) {
    publish_frame(issued_at, FrameDirection::out, options_.outbound_kind,
                  static_cast<std::uint32_t>(payload.size()), payload, false, carried);
  }
  return framed;
}

Status FramedConnection::write_raw(std::string_view bytes) {
  if (!open_) {
    return Error{LocalError::not_connected,
                 fmt::format("{} connection {} is closed", options_.label, peer_)};
  }
  if (Status admitted = admit_to_write_queue(bytes.size()); !admitted) return admitted;
  add(counters_.bytes_out, bytes.size());
  stream_->write(bytes);
  return Ok{};
}

Status FramedConnection::admit_to_write_queue(std::size_t bytes) {
  const std::size_t queued = stream_->queued_bytes();
  const SimTime now = executor_.now();
  const std::uint64_t taken = written_ - std::min<std::uint64_t>(queued, written_);
  if (queued == 0 || taken != taken_) taking_nothing_since_ = now;   // nothing waits, or it took some
  taken_ = taken;
  std::optional<CloseReason> reason;
  if (options_.write_stall_timeout.count() > 0 && queued > 0 &&
      now - taking_nothing_since_ >= options_.write_stall_timeout) {
    reason = CloseReason{PeerError::not_reading,
                         fmt::format("took none of the {} bytes waiting for it for {} ms", queued,
                                     (now - taking_nothing_since_).count() / 1000)};
  } else if (queued + bytes > options_.write_queue_limit_bytes) {
    reason = CloseReason{PeerError::not_reading,
                         fmt::format("{} bytes already queued for it (limit {})", queued,
                                     options_.write_queue_limit_bytes)};
  }
  if (!reason) {
    written_ += bytes;
    return Ok{};
  }
  close(*reason);
  return *reason;
}

void FramedConnection::publish_frame(SimTime at, FrameDirection direction, WireMessageKind kind,
                                     std::uint32_t length_prefix, std::string_view payload,
                                     bool drained, std::optional<AckPair> carried) {
  WireFrame frame;
  frame.wire = options_.wire;
  frame.direction = direction;
  frame.kind = kind;
  frame.length_prefix = length_prefix;
  frame.payload = payload;
  frame.drained = drained;
  if (!drained) frame.ack = carried ? carried : carried_pair(kind, payload);
  frame.peer = peer_;
  options_.events->publish(Event{at, options_.component, frame});
}

void FramedConnection::publish_connection(ConnectionChange change, const CloseReason* reason) {
  if (options_.events == nullptr || !options_.events->active()) return;
  options_.events->publish(Event{executor_.now(), options_.component,
                                 ConnectionEvent{options_.wire, change, peer_, reason}});
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
  decoder_.put_all(
      bytes,
      [this](std::string_view payload) {
        handle_payload(payload);
        return open_;
      },
      [this](std::uint32_t declared_length) {
        add(counters_.oversized_frames_dropped, 1);
        if (options_.events != nullptr && options_.events->active()) {
          publish_frame(last_byte_at_, FrameDirection::in, options_.inbound_kind, declared_length, {}, true);
        }
        warn_oversized(declared_length);
        return open_;
      });
}

void FramedConnection::warn_oversized(std::uint32_t declared_length) {
  // A peer can send nothing but oversized frames, tens of thousands a second: the first of a
  // run is told in full, the rest are counted (a line every period, and at the close).
  const SimTime now = executor_.now();
  if (auto summary = oversized_warnings_.summary(now)) say_oversized(*summary);
  if (oversized_warnings_.occurred(now)) {
    logger_.warn("{} {}: dropped oversized frame of {} bytes (limit {}); connection kept", options_.label, peer_,
                 declared_length, options_.payload_limit_bytes);
  }
}

void FramedConnection::say_oversized(const RepeatedWarning::Summary& summary) {
  logger_.warn("{} {}: dropped {}", options_.label, peer_, summary.text("more oversized frames"));
}

void FramedConnection::handle_payload(std::string_view payload) {
  const bool listening = options_.events != nullptr && options_.events->active();
  inbound_pair_.reset();
  const Status handled = handlers_.on_payload ? handlers_.on_payload(payload) : Status{Ok{}};
  if (listening) {
    publish_frame(last_byte_at_, FrameDirection::in, options_.inbound_kind,
                  static_cast<std::uint32_t>(payload.size()), payload, false, inbound_pair_);
  }
  if (!handled) close(handled.error());
}

void FramedConnection::handle_peer_closed(const std::string& transport_reason) {
  if (!open_) return;
  const Status end = decoder_.finish();
  if (!end) {
    if (may_log()) {
      logger_.warn("{} {}: stream ended inside a frame ({}): {}", options_.label, peer_, transport_reason,
                   end.error().message());
    }
    finish(end.error());
    return;
  }
  if (may_log()) logger_.info("{} {}: peer closed the connection ({})", options_.label, peer_, transport_reason);
  finish(CloseReason{PeerError::closed_by_peer, transport_reason});
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
  close(CloseReason{PeerError::read_timeout, fmt::format("no data from the {} for {} ms",
                                                         options_.label,
                                                         to_whole_ms(options_.read_timeout))});
}

bool FramedConnection::may_log() const {
  return options_.log_budget == nullptr || options_.log_budget->admit(logger_, executor_.now());
}

void FramedConnection::close(CloseReason reason) {
  if (!open_) return;
  if (may_log()) {
    // Our own stop (shutdown, restart) is a normal end: no warning.
    if (reason.code == LocalError::shut_down) {
      logger_.info("closing {} connection {}: {}", options_.label, peer_, reason.message());
    } else {
      logger_.warn("closing {} connection {}: {}", options_.label, peer_, reason.message());
    }
  }
  finish(reason);
}

void FramedConnection::finish(const CloseReason& plain_reason) {
  if (!open_) return;
  // A peer that never spoke OCP framing: the detail says what it looked like instead.
  CloseReason reason = plain_reason;
  if (sniffer_.diagnosis()) reason.detail += "; " + *sniffer_.diagnosis();
  // The owner usually drops its reference inside on_closed; stay alive until we return.
  const auto self = shared_from_this();
  open_ = false;
  if (auto summary = oversized_warnings_.flush(executor_.now())) say_oversized(*summary);
  if (read_timer_ != 0) {
    executor_.cancel(read_timer_);
    read_timer_ = 0;
  }
  if (stream_->is_open()) stream_->close();
  publish_connection(ConnectionChange::closed, &reason);
  if (handlers_.on_closed) handlers_.on_closed(reason);
}

}  // namespace ocp
