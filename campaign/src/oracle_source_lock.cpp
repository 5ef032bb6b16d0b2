// The locked tcp source without a client (oracle_source_lock.hpp).
#include "oracle_source_lock.hpp"

#include <algorithm>

namespace ocp::campaign {
namespace {

// 11 minutes of 100 Hz control messages in flight: more is a link the rule stops judging.
constexpr std::size_t max_pairless_in_flight = 1u << 16;

std::string at_ms(SimTime time) { return std::to_string(time.count() / 1000) + " ms"; }

}  // namespace

SourceLockWatch::SourceLockWatch(const scenario::Scenario& scenario, Report report)
    : scenario_(scenario), report_(std::move(report)) {}

SourceLockWatch::VehicleTrack& SourceLockWatch::track(std::string_view vehicle) {
  auto found = vehicles_.find(vehicle);
  if (found == vehicles_.end()) {
    found = vehicles_.emplace(std::string(vehicle), VehicleTrack{}).first;
    found->second.control_stalls = control_thread_stalls(scenario_, found->first);
  }
  return found->second;
}

void SourceLockWatch::on_event(const Event& event, SimTime now) {
  if (const auto* locked = std::get_if<SourceLocked>(&event.body)) {
    tcp_locked_ = locked->source == ClientSource::tcp;
  } else if (std::holds_alternative<SourceConflict>(event.body)) {
    stopped_ = true;   // no pair from anybody: InvalidMac by another rule (the fault model)
  } else if (const auto* connection = std::get_if<ConnectionEvent>(&event.body)) {
    if (connection->wire == Wire::operator_ && event.component.kind == ComponentKind::player) {
      on_operator_connection(*connection, now);
    }
  } else if (const auto* link = std::get_if<LinkEvent>(&event.body)) {
    if (link->route == LinkRoute::to_streamer && link->kind == LinkMessageKind::operator_control) {
      on_control_link(std::string(event.component.name), *link, now);
    }
  } else if (const auto* fault = std::get_if<FaultEvent>(&event.body)) {
    if (fault->side == FaultSide::vehicle && fault->id == FaultId::InvalidMac) track(fault->vehicle).invalid_mac = fault->active;
  } else if (std::holds_alternative<LatencySample>(event.body) && event.component.kind == ComponentKind::streamer) {
    on_tick(std::string(event.component.name), now);
  }
}

void SourceLockWatch::on_operator_connection(const ConnectionEvent& connection, SimTime now) {
  switch (connection.change) {
    case ConnectionChange::opened:
      client_ = std::string(connection.peer);
      left_at_.reset();   // a new tcp client may take over (judged no further: it may return pairs)
      for (auto& [name, vehicle] : vehicles_) vehicle.reported = false;
      return;
    case ConnectionChange::refused: return;
    case ConnectionChange::closed:
      if (!client_ || *client_ != connection.peer) return;
      client_.reset();
      if (tcp_locked_ && !stopped_) left_at_ = now;
      return;
  }
}

void SourceLockWatch::on_control_link(const std::string& name, const LinkEvent& link, SimTime now) {
  VehicleTrack& vehicle = track(name);
  switch (link.outcome) {
    case LinkOutcome::sent:
      if (left_at_) vehicle.pairless_in_flight.send(link.message_id, {}, max_pairless_in_flight);
      return;
    case LinkOutcome::duplicated: vehicle.pairless_in_flight.duplicate(link.message_id); return;   // as pairless as the first
    case LinkOutcome::dropped: (void)vehicle.pairless_in_flight.take(link.message_id); return;
    case LinkOutcome::delivered:
      vehicle.last_delivered_pairless = vehicle.pairless_in_flight.take(link.message_id).has_value();
      vehicle.last_delivered_at = now;
      return;
  }
}

// At a control tick the Streamer has applied every message delivered so far, unless its
// control thread is stalled (the inbox holds them): not judged then.
void SourceLockWatch::on_tick(const std::string& name, SimTime now) {
  VehicleTrack& vehicle = track(name);
  if (!vehicle.last_delivered_pairless || vehicle.invalid_mac || vehicle.reported || stopped_) return;
  const bool stalled = std::any_of(vehicle.control_stalls.begin(), vehicle.control_stalls.end(), [&](const Window& w) {
    return now >= w.start && now <= w.end;
  });
  if (stalled) return;
  vehicle.reported = true;
  report_(now, name,
          "the Player returned a pair after the locked tcp client left (" +
              (left_at_ ? "at " + at_ms(*left_at_) : std::string("before a new client connected")) +
              "): a control message it sent then reached the Streamer at " + at_ms(vehicle.last_delivered_at) +
              " and InvalidMac is not active (SPEC §4.3 Decision: source tcp locked, no client connected: no pair is "
              "returned)");
}

}  // namespace ocp::campaign
