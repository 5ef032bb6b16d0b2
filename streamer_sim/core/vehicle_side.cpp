// The vehicle connection lifecycle (SPEC §3.1): one active connection; a second one is
// accepted and closed at once; a new connection starts clean.
#include <fmt/format.h>

#include <cstring>
#include <memory>
#include <utility>

#include "ocp/invariant.hpp"
#include "ocp/json_codec.hpp"
#include "ocp/raw_pieces.hpp"
#include "streamer_impl.hpp"

namespace ocp {

void StreamerCore::Impl::accept_vehicle(std::shared_ptr<ByteStream> stream) {
  if (!stream) return;
  const std::string peer = stream->peer_name();
  if (vehicle_connection && vehicle_connection->peer_hung_up()) {
    // The active vehicle has hung up, but its close still waits behind bytes not read yet
    // (a Streamer stopped with SIGSTOP and resumed meets the new connection first): it is no
    // longer connected, so it does not keep the newcomer out.
    const std::shared_ptr<FramedConnection> gone = vehicle_connection;   // on_closed resets ours
    gone->close(CloseReason{PeerError::closed_by_peer,
                            fmt::format("it had hung up already when {} connected", peer)});
  }
  if (vehicle_connection) {
    ++stats.connections_refused;
    const CloseReason reason{LocalError::already_connected,
                             fmt::format("{} is already connected", vehicle_connection->peer())};
    if (connection_log.admit(logger, executor.now())) logger.warn("refused vehicle connection from {}: {}", peer, reason.detail);
    stream->close();
    if (events.active()) {
      events.publish(Event{executor.now(), component(),
                           ConnectionEvent{Wire::vehicle, ConnectionChange::refused, peer, &reason}});
    }
    return;
  }
  ++stats.connections_accepted;
  if (connection_log.admit(logger, executor.now())) logger.info("vehicle connected: {}", peer);
  // Nothing built for a previous connection survives: frames are encoded per tick straight
  // into the active connection, and the old connection (with anything its transport still
  // held) was dropped when it closed.
  FramedConnection::Options options =
      FramedConnection::server_options(Wire::vehicle, config.vehicle_read_timeout, events, component());
  options.write_queue_limit_bytes = config.vehicle_write_queue_limit_bytes;
  options.log_budget = &connection_log;
  FramedConnection::Counters counters;
  counters.bytes_in = &stats.vehicle_bytes_in;
  counters.bytes_out = &stats.vehicle_bytes_out;
  counters.oversized_frames_dropped = &stats.oversized_frames_dropped;
  FramedConnection::Handlers handlers;
  handlers.on_payload = [this](std::string_view payload) -> Status {
    auto response = decode_vehicle_response(payload);
    if (!response) return response.error();
    if (vehicle_connection) vehicle_connection->note_inbound_pair(response->ack);   // for the WireFrame event
    on_vehicle_response(std::move(*response));
    return Ok{};
  };
  handlers.on_closed = [this](const CloseReason& reason) { on_vehicle_closed(reason); };
  vehicle_connection = FramedConnection::open(executor, logger.child("vehicle"), std::move(stream),
                                   std::move(options), counters, std::move(handlers));
  if (started) faults.set(FaultId::VehicleNoResponse, false);
  OCP_INVARIANT(stats.connections_closed <= stats.connections_accepted, "only an accepted connection closes");
}

void StreamerCore::Impl::on_vehicle_response(VehicleResponseMessage&& response) {
  // Responses' pairs are not validated here: they are copied into SEI, and the MAC is checked
  // when the operator returns them.
  ++stats.vehicle_responses_received;
  echoed_pair = response.ack;
  if (response.vehicle_user_data) {
    vehicle_data = std::move(response.vehicle_user_data);
    vehicle_data_arrived_at = executor.now();
  }
}

void StreamerCore::Impl::on_vehicle_closed(const CloseReason& reason) {
  if (!vehicle_connection) return;
  const std::string peer = vehicle_connection->peer();
  ++stats.connections_closed;
  stats.last_close_reason = reason;
  if (connection_log.admit(logger, executor.now())) logger.info("vehicle disconnected: {} ({})", peer, reason.message());
  // Keep the connection object alive until this callback unwinds: the stream callback that
  // led here holds its own reference, so resetting our pointer is safe.
  vehicle_connection.reset();
  if (started) faults.set(FaultId::VehicleNoResponse, true);
  OCP_INVARIANT(stats.connections_closed <= stats.connections_accepted, "only an accepted connection closes");
  OCP_INVARIANT(!started || faults.faults().contains(FaultId::VehicleNoResponse),
                "with no vehicle connected, VehicleNoResponse is raised");
}

Status StreamerCore::Impl::write_raw_to_vehicle(std::string bytes, std::vector<std::size_t> cuts,
                                                Micros gap) {
  if (!vehicle_connection) return Error{LocalError::not_connected, "no vehicle connected"};
  if (events.active()) {
    const std::string_view all(bytes);
    WireFrame frame;
    frame.wire = Wire::vehicle;
    frame.direction = FrameDirection::out;
    frame.kind = WireMessageKind::control;
    if (const auto length_prefix = read_length_prefix(all)) {
      frame.length_prefix = *length_prefix;
      frame.payload = all.substr(frame_header_bytes);
      if (auto decoded = decode_control_message(frame.payload)) frame.ack = decoded->ack;
    }
    frame.peer = vehicle_connection->peer();
    events.publish(Event{executor.now(), component(), frame});
  }
  return write_raw_in_pieces(executor, vehicle_connection, std::move(bytes), cuts, gap);
}

}  // namespace ocp
