// The scenario run's subscriber (observer.hpp): event stream → fault intervals, series,
// counters and invariant violations.
#include "scenario/observer.hpp"

#include <deque>

#include "link_series.hpp"
#include "ocp/impairments.hpp"
#include "ocp/json_codec.hpp"

namespace ocp::scenario {

struct Observer::VehicleState {
  VehicleObservations* out = nullptr;
  std::deque<std::pair<std::uint64_t, SimTime>> pending_pairs;   // control pairs awaiting echo
  std::optional<SimTime> last_control, last_feedback;
  FaultSet control_faults;            // active vehicle-side control-path faults
  bool had_close = false;             // a connection closed: the next opened one is a reconnect
  bool awaiting_first_pair = false;   // first control frame on a new connection not yet seen
  std::optional<std::uint64_t> connection_first_ack;   // ack_time of that first frame
  LinkSeriesBuilder to_streamer_series, to_player_series;
  LinkSeriesBuilder& series(LinkRoute route) { return route == LinkRoute::to_streamer ? to_streamer_series : to_player_series; }
};

Observer::Observer(World& world, ObserverOptions options) : Observer(world.events(), options) {
  world_ = &world;
}

Observer::Observer(EventBus& bus, ObserverOptions options) : options_(options) {
  subscriptions_.push_back(bus.subscribe([this](const Event& event) { on_event(event); }));
}

void Observer::attach_parts() {
  if (world_ == nullptr) return;
  subscriptions_.clear();
  auto handler = [this](const Event& event) { on_event(event); };
  subscriptions_.push_back(world_->player().events().subscribe(handler));
  for (const std::string& vehicle : world_->vehicles()) {
    subscriptions_.push_back(world_->streamer(vehicle).events().subscribe(handler));
    if (!options_.link_events) continue;
    subscriptions_.push_back(world_->link(vehicle).events().subscribe(handler));
    // The links' first impairments were set before anyone listened.
    VehicleState& vehicle_state = state(vehicle);
    vehicle_state.to_streamer_series.set_propagation_delay(world_->link(vehicle).to_streamer().impairments().delay);
    vehicle_state.to_player_series.set_propagation_delay(world_->link(vehicle).to_player().impairments().delay);
  }
}

Observer::~Observer() = default;

Observer::VehicleState& Observer::state(std::string_view vehicle) {
  auto found = states_.find(vehicle);
  if (found == states_.end()) {
    found = states_.emplace(std::string(vehicle), std::make_unique<VehicleState>()).first;
    found->second->out = &observations_.vehicles[std::string(vehicle)];
  }
  return *found->second;
}

namespace {
double to_ms(Micros duration) { return static_cast<double>(duration.count()) / 1000.0; }
}  // namespace

void Observer::on_event(const Event& event) {
  ++observations_.events;
  const SimTime now = event.time - origin_;
  if (const auto* sample = std::get_if<LatencySample>(&event.body)) {
    if (sample->latency_ms) {
      state(event.component.name).out->latency_ms.add(now, static_cast<double>(*sample->latency_ms));
    }
  } else if (const auto* link = std::get_if<LinkEvent>(&event.body)) {
    on_link(event.component.name, *link, now);
  } else if (const auto* frame = std::get_if<WireFrame>(&event.body)) {
    if (frame->wire == Wire::operator_ && frame->kind == WireMessageKind::vehicle_ocp_shared &&
        frame->direction == FrameDirection::out && !options_.feedback_watches.empty()) {
      on_feedback_frame(*frame, now);
      return;
    }
    // Only the Streamer's vehicle wire carries what the series and invariants are about.
    if (frame->wire != Wire::vehicle || event.component.kind != ComponentKind::streamer) return;
    // Any such frame gives the vehicle its entry in the observations, whatever its kind.
    VehicleState& vehicle = state(event.component.name);
    if (frame->kind == WireMessageKind::control && frame->direction == FrameDirection::out) {
      on_control_out(event.component.name, vehicle, *frame, now);
    } else if (frame->kind == WireMessageKind::vehicle_response && frame->direction == FrameDirection::in && frame->ack) {
      on_response_in(event.component.name, vehicle, *frame, now);
    }
  } else if (const auto* fault = std::get_if<FaultEvent>(&event.body)) {
    on_fault(*fault, now);
  } else if (const auto* connection = std::get_if<ConnectionEvent>(&event.body)) {
    if (connection->change != ConnectionChange::opened) record_notable(event, now);
    if (connection->wire != Wire::vehicle || event.component.kind != ComponentKind::streamer) return;
    on_vehicle_connection(event.component.name, *connection);
  } else if (const auto* set = std::get_if<ImpairmentChange>(&event.body)) {
    state(event.component.name).series(set->route).set_propagation_delay(set->impairments->delay);
  } else if (std::holds_alternative<SourceLocked>(event.body) || std::holds_alternative<SourceConflict>(event.body)) {
    record_notable(event, now);
  } else if (const auto* change = std::get_if<ActiveVehicleChange>(&event.body)) {
    std::optional<std::string> vehicle;
    if (change->vehicle) vehicle = std::string(*change->vehicle);
    observations_.active_vehicle.emplace_back(now, std::move(vehicle));
  }
}

// Message counts per route, and the gaps between feedback deliveries at the Player.
void Observer::on_link(std::string_view name, const LinkEvent& link, SimTime now) {
  VehicleState& vehicle = state(name);
  RouteCounters& counters = link.route == LinkRoute::to_streamer ? vehicle.out->to_streamer : vehicle.out->to_player;
  switch (link.outcome) {
    case LinkOutcome::sent: ++counters.sent; break;
    case LinkOutcome::delivered: ++counters.delivered; break;
    case LinkOutcome::dropped: ++counters.dropped; break;
    case LinkOutcome::duplicated: ++counters.duplicated; break;
  }
  vehicle.series(link.route).on_link_event(link, now, link.route == LinkRoute::to_streamer ? vehicle.out->to_streamer_link
                                                                                           : vehicle.out->to_player_link);
  if (link.outcome == LinkOutcome::delivered && link.kind == LinkMessageKind::feedback) {
    if (vehicle.last_feedback) vehicle.out->feedback_gap_ms.add(now, to_ms(now - *vehicle.last_feedback));
    vehicle.last_feedback = now;
  }
}

// A control frame the Streamer wrote to its vehicle: the control gap, the pair its echo will
// be matched against, and — only when asked — the decoded frame.
void Observer::on_control_out(std::string_view name, VehicleState& vehicle, const WireFrame& frame, SimTime now) {
  if (vehicle.last_control) vehicle.out->control_gap_ms.add(now, to_ms(now - *vehicle.last_control));
  vehicle.last_control = now;
  if (frame.ack) {
    vehicle.pending_pairs.emplace_back(frame.ack->ack_time, now);
    if (vehicle.pending_pairs.size() > 4096) vehicle.pending_pairs.pop_front();   // never echoed
    if (vehicle.awaiting_first_pair) {
      vehicle.connection_first_ack = frame.ack->ack_time;
      vehicle.awaiting_first_pair = false;
    }
  }
  record_delivery(name, frame, now);
  if (options_.check_controllers && !vehicle.control_faults.empty()) check_controller(name, vehicle, frame, now);
}

// Decodes the frame only inside a delivery window of its vehicle.
void Observer::record_delivery(std::string_view name, const WireFrame& frame, SimTime now) {
  for (const DeliveryWindow& window : options_.delivery_windows) {
    if (window.vehicle != name || now < window.start || now > window.end) continue;
    if (observations_.deliveries.size() >= delivery_limit) {
      observations_.deliveries_truncated = true;
      break;
    }
    if (auto message = decode_control_message(frame.payload)) {
      Delivery delivery;
      delivery.time = now;
      delivery.vehicle = window.vehicle;
      if (message->controller) {
        delivery.controller = message->controller->is_safe_default() ? Delivery::Controller::default_
                                                                     : Delivery::Controller::driving;
        delivery.controller_value = *message->controller;
      }
      if (message->client_user_data) delivery.user_data_json = message->client_user_data->text;
      observations_.deliveries.push_back(std::move(delivery));
    }
    break;   // one record per frame, however many windows overlap
  }
}

// The invariant: while a control-path fault is active, only the safe default controller goes out.
void Observer::check_controller(std::string_view name, VehicleState& vehicle, const WireFrame& frame, SimTime now) {
  ++vehicle.out->control_frames_checked;
  auto message = decode_control_message(frame.payload);
  const bool violated = !message || (message->controller && !message->controller->is_safe_default());
  if (!violated) return;
  ++observations_.controller_violation_count;
  if (observations_.controller_violations.size() >= violations_kept) return;
  if (!message) {
    observations_.controller_violations.push_back({now, std::string(name), "undecodable control frame"});
  } else {
    observations_.controller_violations.push_back(
        {now, std::string(name), "non-default controller while " + vehicle.control_faults.fault_reason() + " active"});
  }
}

// A vehicle response echoing a pair: the echo delay, and the invariant that a new connection
// never echoes a pair from before it.
void Observer::on_response_in(std::string_view name, VehicleState& vehicle, const WireFrame& frame, SimTime now) {
  const std::uint64_t ack = frame.ack->ack_time;
  if (vehicle.connection_first_ack && ack < *vehicle.connection_first_ack &&
      ++observations_.stale_pair_violation_count <= violations_kept) {
    observations_.stale_pair_violations.push_back(
        {now, std::string(name),
         "pair ack_time " + std::to_string(ack) + " from before the reconnect (first on the new connection: " +
             std::to_string(*vehicle.connection_first_ack) + ")"});
  }
  auto& pending = vehicle.pending_pairs;
  while (!pending.empty() && pending.front().first < ack) pending.pop_front();
  if (!pending.empty() && pending.front().first == ack) {
    vehicle.out->echo_delay_ms.add(now, to_ms(now - pending.front().second));
    pending.pop_front();   // a keep-alive repeating the pair is not a second echo
  }
}

// Fault intervals (both sides), and which control-path faults are active on the vehicle side.
void Observer::on_fault(const FaultEvent& fault, SimTime now) {
  auto& intervals = observations_.faults[{std::string(fault.vehicle), fault.id}];
  if (fault.active) {
    if (intervals.empty() || intervals.back().end) intervals.push_back({now, std::nullopt});
  } else if (!intervals.empty() && !intervals.back().end) {
    intervals.back().end = now;
  }
  if (fault.side == FaultSide::vehicle && is_control_path_fault(fault.id)) {
    state(fault.vehicle).control_faults.set(fault.id, fault.active);
  }
}

// Source locks and conflicts, connection closes and refusals: a few a run, each kept whole.
void Observer::record_notable(const Event& event, SimTime now) {
  NotableEvent out;
  out.time = now;
  out.component = std::string(event.component.name);
  if (const auto* locked = std::get_if<SourceLocked>(&event.body)) {
    out.kind = NotableKind::source_locked;
    out.source = locked->source;
  } else if (const auto* conflict = std::get_if<SourceConflict>(&event.body)) {
    out.kind = NotableKind::source_conflict;
    out.source = conflict->offending;
    out.locked = conflict->locked;
  } else if (const auto* connection = std::get_if<ConnectionEvent>(&event.body)) {
    out.kind = connection->change == ConnectionChange::refused ? NotableKind::connection_refused : NotableKind::connection_closed;
    out.wire = connection->wire;
    if (connection->reason != nullptr) out.reason = connection->reason->message();
  }
  if (observations_.notable_events.size() < 4096) observations_.notable_events.push_back(std::move(out));
}

// Counts connections; after a close, the next connection's first pair starts the stale-pair check.
void Observer::on_vehicle_connection(std::string_view name, const ConnectionEvent& connection) {
  VehicleState& vehicle = state(name);
  if (connection.change == ConnectionChange::opened) {
    ++vehicle.out->connections_opened;
    if (vehicle.had_close) {
      ++observations_.reconnects;
      vehicle.awaiting_first_pair = true;
      vehicle.connection_first_ack.reset();
    }
    vehicle.pending_pairs.clear();
  } else if (connection.change == ConnectionChange::closed) {
    vehicle.had_close = true;
  }
}

}  // namespace ocp::scenario
