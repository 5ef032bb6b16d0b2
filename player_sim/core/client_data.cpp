// Client data sources (tcp, webview, plugin): locking (SPEC §4.3), applying ClientOcpShared
// (§4.2), the latency-loop echo (§5 step 6) and the single tcp client connection.
#include <utility>

#include <fmt/format.h>

#include "ocp/json_codec.hpp"
#include "ocp/mutants.hpp"
#include "ocp/raw_pieces.hpp"

#include "player_impl.hpp"

namespace ocp {
namespace {

// Said with the last name a WarnedNames remembers, so the summaries that follow make sense.
std::string remembering_no_more(const WarnedNames& names) {
  if (!names.full()) return {};
  return fmt::format(" ({} names warned about: further unknown names are only counted, every {})",
                     names.capacity(), format_span(RepeatedWarning::default_period));
}

}  // namespace

void PlayerCore::Impl::on_client_data(ClientSource source, const ClientOcpShared& data) {
  ++stats.client_messages_received;
  bool keep_alive = is_keep_alive(source, data);
#ifdef OCP_MUTANTS
  if (mutant_active(Mutant::keep_alive_locks_source)) keep_alive = false;
#endif
  if (keep_alive) {
    // Its bytes already reset the :4001 read timer; it carries nothing to apply or lock on.
    ++stats.client_keep_alives;
    return;
  }
  const bool was_locked = source_lock.locked().has_value();
  if (!source_lock.admit(source, logger)) {
    if (source_lock.conflict_just_happened()) {
      ++stats.source_conflicts;
      stop_all_client_data();
      if (events.active()) publish(SourceConflict{*source_lock.locked(), source});
    }
    ++stats.client_messages_ignored;
    return;
  }
  if (!was_locked && events.active()) publish(SourceLocked{source});
  if (source == ClientSource::tcp) tcp_lock_without_client_logged = false;   // a tcp client took over
  apply_client_data(source, data);
}

void PlayerCore::Impl::apply_client_data(ClientSource source, const ClientOcpShared& data) {
  const SimTime now = executor.now();
  if (data.active_vehicle) {
    if (vehicles.contains(*data.active_vehicle)) {
      warned_unknown_active.clear();
    } else if (warned_unknown_active.first_time(*data.active_vehicle, now)) {
      // Once per episode: a client repeats its selection in every message (100 Hz).
      logger.warn("active_vehicle '{}' from {} is not a linked vehicle; no vehicle is active{}",
                  *data.active_vehicle, client_source_name(source), remembering_no_more(warned_unknown_active));
    }
    selected_vehicle = data.active_vehicle;
  }
  for (const auto& [name, entry] : data.client_user_data) {
    const auto found = vehicles.find(name);
    if (found == vehicles.end()) {
      ++stats.unknown_vehicle_entries;
      if (warned_unknown_entries.first_time(name, now)) {
        logger.warn("client_user_data for unknown vehicle '{}' from {} ignored{}", name,
                    client_source_name(source), remembering_no_more(warned_unknown_entries));
      }
      continue;
    }
    VehicleClientState& state = found->second.client;
    state.user_data = entry.user_data;
    state.disable_gamepad = entry.ocp_disable_gamepad.value_or(false);
    if (source != ClientSource::webview) {
      // tcp and plugin clients echo the pair themselves: both halves or nothing.
      state.returned_pair.reset();
      if (entry.ack_time_returned && entry.ack_time_mac_returned) {
        state.returned_pair = AckPair{*entry.ack_time_returned, *entry.ack_time_mac_returned};
      }
    }
  }
  if (source == ClientSource::webview) {
    // The web view sends no pair: the Player injects the latest one into each of its messages.
    for (auto& [name, link] : vehicles) link.client.returned_pair = link.latest_sei;
  }
}

void PlayerCore::Impl::summarise_repeated_warnings(SimTime now) {
  if (auto summary = warned_unknown_entries.summary(now)) {
    logger.warn("… and {} ignored", summary->text("more client_user_data entries for unknown vehicle names"));
  }
  if (auto summary = warned_unknown_active.summary(now)) {
    logger.warn("… and {}", summary->text("more unknown active_vehicle names"));
  }
  if (auto summary = warned_unknown_senders.summary(now)) {
    logger.warn("… and {} dropped", summary->text("more messages from unknown vehicle names"));
  }
}

void PlayerCore::Impl::stop_all_client_data() {
  // User data and every external echo stop; no fallback to self-echo (see echo_pair).
  // ocp_disable_gamepad and the selected vehicle keep their values on purpose.
  for (auto& [name, link] : vehicles) {
    link.client.user_data.reset();
    link.client.returned_pair.reset();
  }
}

std::optional<AckPair> PlayerCore::Impl::echo_pair(const VehicleLink& link) const {
  if (source_lock.stopped()) return std::nullopt;
  if (!source_lock.locked()) return link.latest_sei;  // self-echo
  return link.client.returned_pair;
}

void PlayerCore::Impl::accept_client(std::shared_ptr<ByteStream> stream) {
  if (!stream) return;
  if (client && client->peer_hung_up()) {
    // Gone already, its close not read yet (see StreamerCore's accept_vehicle): not connected.
    const std::shared_ptr<FramedConnection> gone = client;   // on_client_closed resets ours
    gone->close(CloseReason{PeerError::closed_by_peer,
                            fmt::format("it had hung up already when {} connected", stream->peer_name())});
  }
  if (client && client->is_open()) {
    ++stats.client_connections_refused;
    const CloseReason reason{LocalError::already_connected,
                             fmt::format("client {} is already connected (one client at a time)",
                                         client->peer())};
    const std::string peer = stream->peer_name();
    if (connection_log.admit(logger, executor.now())) logger.warn("tcp client {} refused: {}", peer, reason.detail);
    stream->close();
    if (events.active()) {
      publish(ConnectionEvent{Wire::operator_, ConnectionChange::refused, peer, &reason});
    }
    return;
  }
  ++stats.client_connections_accepted;
  if (connection_log.admit(logger, executor.now())) logger.info("tcp client {} connected", stream->peer_name());
  FramedConnection::Options options =
      FramedConnection::server_options(Wire::operator_, config.client_read_timeout, events, component());
  options.log_budget = &connection_log;
  FramedConnection::Counters counters;
  counters.oversized_frames_dropped = &stats.client_oversized_frames;
  counters.bytes_out = &stats.client_bytes_out;
  FramedConnection::Handlers handlers;
  handlers.on_payload = [this](std::string_view payload) -> Status {
    Result<ClientOcpShared> message = decode_client_ocp_shared(payload);
#ifdef OCP_MUTANTS
    if (!message && mutant_active(Mutant::operator_bad_frame_kept)) return Ok{};
#endif
    if (!message) return message.error();
    on_client_data(ClientSource::tcp, *message);
    return Ok{};
  };
  handlers.on_closed = [this](const CloseReason& reason) { on_client_closed(reason); };
  client_too_large.reset();
  client = FramedConnection::open(executor, logger.child("tcp"), std::move(stream),
                                  std::move(options), counters, std::move(handlers));
}

void PlayerCore::Impl::send_to_client(const VehicleOcpShared& shared) {
  if (client_output_paused) return;
  encode_vehicle_ocp_shared(shared, client_json_buffer);
  const Status sent = client->send(client_json_buffer);
  if (sent) {
    ++stats.client_frames_sent;
    if (client_too_large) {
      // The episode of oversized frames is over; the next one is warned about again.
      logger.child("tcp").info("tcp client {}: VehicleOcpShared fits again after {} frames not sent",
                               client->peer(), client_too_large->frames);
      client_too_large.reset();
    }
    return;
  }
  if (sent.error().code != LocalError::frame_too_large) return;
  // Never send an oversized frame (SPEC §2); the client misses this one. One warning per
  // episode (a run of oversized frames): a large fleet would otherwise log every frame. The
  // status line and the web view show the episode while it lasts (client_frame_too_large).
  ++stats.client_frames_too_large;
  const bool first = !client_too_large;
  if (first) client_too_large = ClientFrameTooLarge{0, max_payload_bytes, 0, 0};
  client_too_large->bytes = client_json_buffer.size();
  client_too_large->vehicles = shared.vehicle_feedback.size();
  ++client_too_large->frames;
  if (!first) return;
  logger.child("tcp").warn(
      "tcp client {}: VehicleOcpShared not sent: {} bytes is over the {}-byte frame limit (SPEC §2), so the "
      "client receives nothing until it fits again. Make it smaller: fewer vehicles ({} linked), smaller "
      "vehicle_user_data, fewer cameras",
      client->peer(), client_too_large->bytes, max_payload_bytes, client_too_large->vehicles);
}

Status PlayerCore::Impl::write_raw_to_client(std::string bytes, std::vector<std::size_t> cuts, Micros gap) {
  if (!client) return Error{LocalError::not_connected, "no tcp client connected"};
  if (events.active()) {
    // One WireFrame per frame the bytes hold; a truncated last frame carries what is there.
    std::string_view rest(bytes);
    while (const auto length_prefix = read_length_prefix(rest)) {
      WireFrame frame;
      frame.wire = Wire::operator_;
      frame.direction = FrameDirection::out;
      frame.kind = WireMessageKind::vehicle_ocp_shared;
      frame.length_prefix = *length_prefix;
      frame.payload = rest.substr(frame_header_bytes, frame.length_prefix);
      frame.peer = client->peer();
      publish(frame);
      rest.remove_prefix(frame_header_bytes + frame.payload.size());
    }
  }
  return write_raw_in_pieces(executor, client, std::move(bytes), cuts, gap);
}

void PlayerCore::Impl::on_client_closed(const CloseReason& reason) {
  ++stats.client_connections_closed;
  const bool told = client && connection_log.admit(logger, executor.now());
  if (told) logger.info("tcp client {} disconnected ({})", client->peer(), reason.message());
  last_client_close_reason = reason;
  client_too_large.reset();   // nothing is sent without a client
  client.reset();  // the connection keeps itself alive until its callback returns
  bool forget_pairs = source_lock.locked() == ClientSource::tcp;
#ifdef OCP_MUTANTS
  if (mutant_active(Mutant::locked_client_pair_kept)) forget_pairs = false;
#endif
  if (forget_pairs) {
    // SPEC §4.3 Decision: the locked tcp client left, so no pair is returned until a new tcp
    // client sends one. Its last pair would only age on the Streamer (HighLatency), hiding
    // that the loop is not closed (InvalidMac).
    for (auto& [name, link] : vehicles) link.client.returned_pair.reset();
  }
  // Said with its disconnect line, so a storm of clients that each take over and leave stays
  // within the connection log budget; one the budget left out says it at the next told leave.
  if (told && source_lock.locked() == ClientSource::tcp && !source_lock.stopped() && !tcp_lock_without_client_logged) {
    tcp_lock_without_client_logged = true;
    logger.warn("{} (the lock stays with the tcp source: a new TCP client may take over, nothing else may)",
                tcp_lock_without_client_text);
  }
}

}  // namespace ocp
