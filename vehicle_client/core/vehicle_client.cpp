// Connection lifecycle and the receive path of the reference vehicle client. The response
// encoding (including the misbehaviour switches) lives in response_writer.cpp.
#include "vehicle_client/vehicle_client.hpp"

#include "ocp/framing_diagnosis.hpp"
#include "ocp/json_codec.hpp"

namespace ocp {

std::string_view disconnect_kind_name(DisconnectKind kind) {
  switch (kind) {
    case DisconnectKind::none: return "none";
    case DisconnectKind::peer_closed: return "peer_closed";
    case DisconnectKind::protocol_error: return "protocol_error";
    case DisconnectKind::not_an_ocp_server: return "not_an_ocp_server";
    case DisconnectKind::server_silent: return "server_silent";
    case DisconnectKind::misbehaved: return "misbehaved";
  }
  return "unknown";
}

std::optional<std::string> validate(const VehicleClientConfig& config) {
  if (auto problem = validate(config.safety)) return problem;
  if (auto problem = validate(config.vehicle)) return problem;
  if (!(config.start.lat >= -89.0 && config.start.lat <= 89.0)) return "start latitude must be in [-89, 89]";
  if (!(config.start.lon >= -180.0 && config.start.lon <= 180.0)) return "start longitude must be in [-180, 180]";
  if (config.response_period.count() <= 0) return "response period must be positive";
  if (config.model_step.count() <= 0) return "model step must be positive";
  if (config.model_grid.count() < 0) return "model grid must be >= 0 (0: ticks from attach)";
  if (config.server_silence_limit.count() <= 0) return "server silence limit must be positive";
  if (config.user_data_limit_bytes == 0 || config.user_data_limit_bytes > max_payload_bytes / 2) {
    return "user data limit must be in [1, 8192] bytes";
  }
  if (config.misbehave.delay_responses.count() < 0) return "response delay must be >= 0";
  return std::nullopt;
}

VehicleClient::VehicleClient(Executor& executor, VehicleClientConfig config, Logger logger)
    : executor_(executor),
      config_(std::move(config)),
      logger_(std::move(logger)),
      safety_(config_.safety),
      model_(config_.vehicle, config_.start, config_.start_heading_deg),
      model_timer_(executor_, config_.model_step, [this](SimTime deadline) { on_model_tick(deadline); }) {
  model_.reset_time(executor_.now());
  refresh_user_data();
  if (config_.misbehave.any()) {
    logger_.warn("MISBEHAVING on purpose (tests/demos only): {}", config_.misbehave.describe());
  }
}

VehicleClient::~VehicleClient() {
  liveness_.revoke();
  detach();
  // Keep-alive tasks hold a plain `this` (response_writer.cpp): none may outlive the client.
  if (keepalive_timer_ != 0) executor_.cancel(keepalive_timer_);
}

const SafetyOutput& VehicleClient::safety() const { return safety_.output(); }
const VehicleState& VehicleClient::vehicle() const { return model_.state(); }

bool VehicleClient::connected() const { return stream_ && stream_->is_open(); }

void VehicleClient::set_on_disconnected(std::function<void(const std::string& reason)> callback) {
  on_disconnected_ = std::move(callback);
}

void VehicleClient::attach(std::shared_ptr<ByteStream> stream) {
  if (stream_) detach();
  const SimTime now = executor_.now();
  stream_ = std::move(stream);
  const std::uint64_t id = ++connection_id_;
  decoder_.reset();
  sniffer_ = FramingSniffer(first_frame_implausible_from);
  seen_valid_control_ = false;
  bytes_at_attach_ = stats_.bytes_received;
  echo_pair_.reset();
  last_response_time_.reset();
  ++stats_.connections;
  // A new connection is a new session: the operator must enable driving again.
  safety_.reset(now);
  if (!model_timer_.running()) {
    model_.reset_time(now);
    model_timer_.start(first_model_tick(now));
  }
  logger_.debug("attached to {}", stream_->peer_name());

  stream_->set_no_delay(true);
  const LivenessToken::Watch owner = liveness_.watch();
  stream_->set_handlers(ByteStreamHandlers{
      .on_bytes =
          [this, owner, id](std::string_view bytes) {
            if (owner.alive() && id == connection_id_) on_bytes(bytes);
          },
      .on_closed =
          [this, owner, id](const std::string& reason) {
            if (owner.alive() && id == connection_id_) on_closed(reason);
          },
  });
  arm_silence_check(now + config_.server_silence_limit);
}

void VehicleClient::detach() {
  if (!stream_) return;
  std::shared_ptr<ByteStream> stream = std::move(stream_);
  release_connection();
  stream->close();
}

void VehicleClient::release_connection() {
  stream_.reset();
  ++connection_id_;  // callbacks of the old connection become no-ops
  if (keepalive_timer_ != 0) executor_.cancel(keepalive_timer_);
  if (silence_timer_ != 0) executor_.cancel(silence_timer_);
  keepalive_timer_ = 0;
  silence_timer_ = 0;
}

void VehicleClient::on_closed(const std::string& reason) {
  std::string detail = reason.empty() ? "connection closed by server" : reason;
  if (const Status tail = decoder_.finish(); !tail.ok()) detail += " (" + tail.error().message() + ")";
  release_connection();
  finish_disconnect(DisconnectKind::peer_closed, detail);
}

void VehicleClient::close_with(DisconnectKind kind, const std::string& reason) {
  std::shared_ptr<ByteStream> stream = std::move(stream_);
  release_connection();
  if (stream) stream->close();
  finish_disconnect(kind, reason);
}

void VehicleClient::finish_disconnect(DisconnectKind kind, const std::string& reason) {
  stats_.last_disconnect_kind = kind;
  stats_.last_disconnect_reason = reason;
  logger_.info("disconnected: {}", reason);
  if (on_disconnected_) on_disconnected_(reason);
}

// Why the client deframes with FrameDecoder::put_all (the loop FramedConnection runs too)
// and not through a FramedConnection: FramedConnection is the servers' side of SPEC §2, and
// its connection rules are not the client's — using it would change what the client does:
//  * FramedConnection's read timeout restarts on any byte. The client's silence limit
//    (on_silence_check) counts from the last valid control message — a server that sends
//    only oversized frames is still silent — and before the first one the client ends the
//    connection as not_an_ocp_server.
//  * FramedConnection drains an oversized first frame and keeps the connection (its sniffer
//    only warns, from 16 MiB). To the client a first frame over the payload limit means the
//    peer is no OCP server (check_first_header).
//  * FramedConnection closes a peer once 1 MiB is queued for it (not_reading). The client
//    has no write-queue limit, and its misbehaviour switches write frames that send()
//    refuses (oversized_frames) or write them later (delay_responses).
//  * FramedConnection reports a close as a CloseReason, with the sniffer's diagnosis
//    appended, and logs it in its own words; the client reports a DisconnectKind and reasons
//    that its stats, its tests and the conformance suite read.
// Not a reason: the echo between ControlMessageDecoder::start and finish would fit inside
// FramedConnection's on_payload.
void VehicleClient::on_bytes(std::string_view bytes) {
  stats_.bytes_received += bytes.size();
  if (!seen_valid_control_ && !check_first_header(bytes)) return;
  const std::uint64_t id = connection_id_;
  decoder_.put_all(
      bytes,
      [this, id](std::string_view payload) {
        handle_payload(payload);
        return id == connection_id_;  // false: the payload closed the connection
      },
      [this](std::uint32_t declared_length) {
        ++stats_.oversized_frames_dropped;
        logger_.warn("dropped an oversized control frame ({} bytes > {} limit)", declared_length,
                     max_payload_bytes);
        return true;
      });
}

bool VehicleClient::check_first_header(std::string_view bytes) {
  // An OCP server's first frame is a small control message. A declared length over the limit
  // means the peer speaks something else (HTTP's "HTTP" reads as ~1.3 GB): say so at once
  // instead of silently draining gigabytes.
  const std::optional<std::string> diagnosis = sniffer_.observe(bytes);
  if (!diagnosis) return true;
  close_with(DisconnectKind::not_an_ocp_server,
             fmt::format("not an OCP server: first frame declares {} bytes (limit {}); {}",
                         sniffer_.declared_length().value_or(0), max_payload_bytes, *diagnosis));
  return false;
}

void VehicleClient::handle_payload(std::string_view payload) {
  // Latency first: once the server has proved it speaks OCP, the pair is echoed as soon as the
  // message is tokenized, before the rest of it is decoded and validated (ControlMessageDecoder:
  // one tokenization, the same result as decode_control_message).
  const std::optional<AckPair> pair = control_decoder_.start(payload);
  const bool echoed = seen_valid_control_ && pair.has_value();
  if (echoed) echo(*pair);
  Result<OcpControlMessage> message = control_decoder_.finish();
  if (!message.ok()) {
    if (!seen_valid_control_) {
      close_with(DisconnectKind::not_an_ocp_server,
                 "not an OCP server: first frame is not an OCP control message (" +
                     message.error().message() + ")");
    } else {
      close_with(DisconnectKind::protocol_error, "bad control message from server: " + message.error().message());
    }
    return;
  }
  if (!echoed) echo(message->ack);
  handle_control_message(*message);
}

void VehicleClient::echo(const AckPair& pair) {
  if (!(config_.misbehave.stop_echo && echo_pair_)) echo_pair_ = pair;
  send_response(ResponseCause::echo);
}

void VehicleClient::handle_control_message(const OcpControlMessage& message) {
  const SimTime now = executor_.now();
  seen_valid_control_ = true;
  ++stats_.control_messages_received;
  stats_.last_ack = message.ack;
  stats_.last_control_time = now;
  stats_.last_latency_ms = message.telemetry.latency_ms;
  if (message.telemetry.fault != stats_.last_telemetry_fault ||
      (message.telemetry.fault && message.telemetry.fault_reason != stats_.last_fault_reason)) {
    const FlapSummariser::Verdict verdict = fault_flaps_.on_edge(message.telemetry.fault, now);
    if (verdict.log_edge && message.telemetry.fault) {
      logger_.warn("Streamer reports fault: {}", message.telemetry.fault_reason);
    } else if (verdict.log_edge) {
      logger_.info("Streamer faults cleared");
    }
    if (verdict.summary) {
      logger_.warn("{} (now: {})", *verdict.summary,
                   message.telemetry.fault ? message.telemetry.fault_reason : std::string("no fault"));
    }
    stats_.last_telemetry_fault = message.telemetry.fault;
    stats_.last_fault_reason = message.telemetry.fault_reason;  // display only
  } else if (fault_flaps_.flapping()) {
    if (auto line = fault_flaps_.on_steady(now)) logger_.warn("{}", *line);
  }
  safety_.on_control_message(message, now);
}

// Not FramedConnection's read timeout: silence is counted from the last valid control
// message, not the last byte (see on_bytes).
void VehicleClient::arm_silence_check(SimTime deadline) {
  const LivenessToken::Watch owner = liveness_.watch();
  silence_timer_ = executor_.call_at(deadline, [this, owner] {
    if (owner.alive()) on_silence_check();
  });
}

void VehicleClient::on_silence_check() {
  silence_timer_ = 0;
  if (!stream_) return;
  const SimTime now = executor_.now();
  const double limit_s = std::chrono::duration<double>(config_.server_silence_limit).count();
  if (!seen_valid_control_) {
    // Only bytes that are not OCP framing make it "not an OCP server", and those have closed
    // the connection already (check_first_header, handle_payload). Silence says nothing
    // about what the server is: a Streamer stopped with SIGSTOP still completes connects.
    const std::uint64_t received = stats_.bytes_received - bytes_at_attach_;
    close_with(DisconnectKind::server_silent,
               received == 0
                   ? fmt::format("no data from the server for {:g} s after connecting (is it stopped or hung?)",
                                 limit_s)
                   : fmt::format("no whole control message from the server for {:g} s after connecting "
                                 "({} bytes arrived: part of a frame)",
                                 limit_s, received));
    return;
  }
  const SimTime deadline = *stats_.last_control_time + config_.server_silence_limit;
  if (deadline <= now) {
    close_with(DisconnectKind::server_silent,
               fmt::format("server stopped sending control messages for {:g} s", limit_s));
    return;
  }
  arm_silence_check(deadline);
}

SimTime VehicleClient::first_model_tick(SimTime attached) const {
  const SimTime earliest = attached + config_.model_step;
  const std::int64_t grid = config_.model_grid.count();
  if (grid <= 0) return earliest;
  return SimTime{(earliest.count() + grid - 1) / grid * grid};
}

void VehicleClient::on_model_tick(SimTime deadline) {
  const SafetyOutput before = safety_.output();
  const SafetyOutput& after = safety_.evaluate(deadline);
  model_.advance_to(deadline, after.command, config_.model_step);
  if (after.drive_state != before.drive_state) {
    logger_.info("drive state: {}", drive_state_name(after.drive_state));
  }
  if (after.reasons != before.reasons) {
    std::string reasons;
    for (std::string_view name : after.reasons.names()) {
      if (!reasons.empty()) reasons += ", ";
      reasons += name;
    }
    logger_.debug("safe state: {}", after.safe_state ? reasons : "off (commands pass through)");
  }
  refresh_user_data();
}

}  // namespace ocp
