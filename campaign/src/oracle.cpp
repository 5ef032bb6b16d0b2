// The oracle (oracle.hpp): event dispatch, safety, the latency loop and conservation. The
// fault model and liveness are in oracle_faults.cpp.
#include <rapidjson/document.h>

#include <algorithm>
#include <cmath>

#include "oracle_source_lock.hpp"
#include "oracle_state.hpp"
#include "world/world.hpp"

namespace ocp::campaign {

namespace {
constexpr std::size_t max_kept_violations = 50;
constexpr std::size_t max_issued_pairs = 1u << 16;    // 11 minutes of 10 ms ticks

}  // namespace

std::string_view check_name(Check check) {
  switch (check) {
    case Check::safety_controller: return "safety.controller";
    case Check::safety_monitor: return "safety.monitor";
    case Check::safety_frame_size: return "safety.frame_size";
    case Check::fault_model: return "fault_model";
    case Check::latency_loop: return "latency_loop";
    case Check::stale_pair: return "latency_loop.stale_pair";
    case Check::liveness: return "liveness";
    case Check::conservation: return "conservation";
    case Check::determinism: return "determinism";
    case Check::operator_port: return "operator.port";
    case Check::operator_feedback: return "operator.feedback";
    case Check::client_echo: return "client.echo";
    case Check::client_reconnect: return "client.reconnect";
    case Check::client_alive: return "client.alive";
  }
  return "?";
}

// As client_world.cpp sets the tolerances (judge_timing off) and prepares the world (no
// operator client), and as only client worlds have a ClientWatch.
std::string_view not_judged_because(Check check, bool client_worlds, bool client_real_time) {
  switch (check) {
    case Check::fault_model:
    case Check::latency_loop:
    case Check::liveness: return client_real_time ? "not judged in real time" : "";
    case Check::determinism:
      if (client_real_time) return "not judged in real time";
      return client_worlds ? "one run of the client per world" : "";
    case Check::operator_port:
    case Check::operator_feedback: return client_worlds ? "no operator client in client worlds" : "";
    case Check::client_echo:
    case Check::client_reconnect:
    case Check::client_alive: return client_worlds ? "" : "only with --client";
    default: return "";
  }
}

Oracle::Oracle(const scenario::Scenario& scenario, OracleTolerances tolerances)
    : scenario_(scenario), tolerances_(tolerances) {
  const SimTime quiet = quiet_point(scenario);
  liveness_at_ = quiet + liveness_bound(scenario);
  liveness_possible_ = liveness_at_ < scenario.duration;
  for (const VehicleSpec& spec : scenario.world.vehicles) {
    auto state = std::make_unique<VehicleState>();
    state->name = spec.name;
    state->spec = &spec;
    state->control_stalls = control_thread_stalls(scenario, spec.name);
    state->frame_stalls = frame_loop_stalls(scenario, spec.name);
    for (const CameraConfig& camera : spec.streamer.cameras) {
      CameraWatch watch;
      watch.name = camera.name;
      watch.frame_period = Micros{static_cast<std::int64_t>(std::ceil(1e6 / camera.fps))};
      if (camera.drop_detector) watch.stalls = camera_stalls(scenario, spec.name, camera.name);
      for (const Window& window : watch.stalls) {
        bool certain = true;
        for (const Window& other : watch.stalls) {
          if (&other != &window && other.end > window.start && other.end < window.end) certain = false;
        }
        watch.certain.push_back(certain);
      }
      state->cameras.push_back(std::move(watch));
    }
    state->start_to_streamer = state->now_to_streamer = spec.to_streamer;
    state->start_to_player = state->now_to_player = spec.to_player;
    for (const scenario::TimelineEvent& event : scenario.timeline) {
      if (const auto* set = std::get_if<scenario::SetMisbehaviour>(&event.action); set && set->vehicle == spec.name) {
        state->misbehaving_at_end = set->misbehave.any();
      }
    }
    state->misbehaving_at_end = state->misbehaving_at_end || spec.client.misbehave.any();
    vehicles_.emplace(spec.name, std::move(state));
  }
  if (scenario.operator_client.connect) {
    operator_ = std::make_unique<OperatorPort>();
    operator_->read_timeout = scenario.world.player.client_read_timeout;
    for (const scenario::TimelineEvent& event : scenario.timeline) {
      if (const auto* set = std::get_if<scenario::SetOperatorMisbehaviour>(&event.action)) {
        operator_->misbehaving_at_end = set->misbehave.any();
      }
    }
  }
}

Oracle::~Oracle() = default;

void Oracle::attach(World& world) {
  world_ = &world;
  origin_ = world.executor().now();
  source_lock_watch_ = std::make_unique<SourceLockWatch>(scenario_, [this](SimTime now, const std::string& vehicle, std::string detail) {
    report(Check::operator_port, now, vehicle, std::move(detail));
  });
  subscriptions_.push_back(world.events().subscribe([this](const Event& event) { on_event(event); }));
}

Oracle::VehicleState& Oracle::vehicle(std::string_view name) {
  auto found = vehicles_.find(name);
  if (found == vehicles_.end()) {
    // Not in the model: an event about a vehicle nobody configured is itself worth reporting.
    auto state = std::make_unique<VehicleState>();
    state->name = std::string(name);
    found = vehicles_.emplace(std::string(name), std::move(state)).first;
  }
  return *found->second;
}

void Oracle::report(Check check, SimTime now, const std::string& vehicle, std::string detail,
                    std::optional<FaultId> fault, bool should_be_active,
                    std::optional<scenario::ExpectationKind> regression) {
  ++violation_count_;
  if (violations_.size() < max_kept_violations) {
    violations_.push_back({check, now, vehicle, std::move(detail), fault, should_be_active, std::move(regression)});
  }
}

void Oracle::on_event(const Event& event) {
  ++events_;
  if (source_lock_watch_) source_lock_watch_->on_event(event, event.time - origin_);
  std::visit(
      [&](const auto& body) {
        using T = std::decay_t<decltype(body)>;
        if constexpr (std::is_same_v<T, WireFrame>) {
          on_wire_frame(event, body);
        } else if constexpr (std::is_same_v<T, FaultEvent>) {
          on_fault(event, body);
        } else if constexpr (std::is_same_v<T, ConnectionEvent>) {
          on_connection(event, body);
        } else if constexpr (std::is_same_v<T, LatencySample>) {
          on_latency_sample(event, body);
        } else if constexpr (std::is_same_v<T, LinkEvent>) {
          on_link(event, body);
        } else if constexpr (std::is_same_v<T, ImpairmentChange>) {
          VehicleState& state = vehicle(event.component.name);
          (body.route == LinkRoute::to_streamer ? state.now_to_streamer : state.now_to_player) = *body.impairments;
          if (body.impairments->duplicate_probability > 0) {
            state.links[static_cast<int>(body.route)].duplicates_possible = true;
          }
        } else if constexpr (std::is_same_v<T, GamepadChange>) {
          gamepad_plugged_ = body.plugged;
        } else if constexpr (std::is_same_v<T, SourceLocked>) {
          source_locked_ = true;
          if (operator_) on_source_locked(event.time - origin_, body);
        } else if constexpr (std::is_same_v<T, SourceConflict>) {
          source_conflict_ = true;
        } else if constexpr (std::is_same_v<T, ActiveVehicleChange>) {
          selected_ = body.vehicle ? std::optional<std::string>(std::string(*body.vehicle)) : std::nullopt;
          selected_since_ = event.time - origin_;
        }
      },
      event.body);
}

// Safety (frame size, controller during control-path faults) and the latency loop's pairs.
void Oracle::on_wire_frame(const Event& event, const WireFrame& frame) {
  const SimTime now = event.time - origin_;
  if (frame.direction == FrameDirection::out && frame.length_prefix > max_oracle_frame_payload &&
      (event.component.kind == ComponentKind::streamer || event.component.kind == ComponentKind::player)) {
    report(Check::safety_frame_size, now, std::string(event.component.name),
           "a " + std::to_string(frame.length_prefix) + "-byte frame was written (limit 16384)");
  }
  if (frame.wire == Wire::operator_ && event.component.kind == ComponentKind::player && operator_) {
    on_operator_frame(now, frame);
    return;
  }
  if (frame.wire != Wire::vehicle || event.component.kind != ComponentKind::streamer || !frame.ack) return;
  VehicleState& state = vehicle(event.component.name);
  if (frame.direction == FrameDirection::out && frame.kind == WireMessageKind::control) {
    if (state.issued.size() >= max_issued_pairs) state.issued.pop_front();
    state.issued.push_back({now, frame.ack->ack_time, frame.ack->ack_time_mac, false});
    check_controller(state, now, frame);
    return;
  }
  if (frame.direction != FrameDirection::in || frame.kind != WireMessageKind::vehicle_response) return;
  // An echo: which issued pair is it? Pairs are issued in increasing ack_time order.
  auto found = std::lower_bound(state.issued.begin(), state.issued.end(), frame.ack->ack_time,
                                [](const IssuedPair& pair, std::uint64_t ack) { return pair.ack_time < ack; });
  if (found == state.issued.end() || found->ack_time != frame.ack->ack_time) return;   // not ours, or too old
  if (found->mac == frame.ack->ack_time_mac) found->echoed_with_mac = true;
  if (state.had_close && found->issued < state.connection_opened) {
    report(Check::stale_pair, now, state.name,
           "the vehicle echoed ack_time " + std::to_string(found->ack_time) + ", issued at " +
               std::to_string(found->issued.count()) + " us, before its connection opened at " +
               std::to_string(state.connection_opened.count()) + " us");
  }
}

// SPEC §3.2: while a control-path fault is active, the controller is the default one or null.
void Oracle::check_controller(VehicleState& state, SimTime now, const WireFrame& frame) {
  bool control_fault = false;
  for (std::size_t f = 0; f < fault_count; ++f) {
    const auto id = static_cast<FaultId>(f);
    if (oracle_control_path(id) && state.reported_vehicle.has(id)) control_fault = true;
  }
  // The oracle's own view too: no operator message for longer than the timeout. Only where
  // timing is judged: in real time the Streamer reads its clock at the tick and the frame's
  // event is stamped later, so a thread preempted in between (a loaded machine) would cross the
  // line here and not in the Streamer. The faults it reported are ordered, not timed.
  if (state.spec != nullptr && tolerances_.judge_timing) {
    const SimTime last = state.last_control_delivered.value_or(SimTime{0});
    if (now - last > state.spec->streamer.no_control_timeout) control_fault = true;
  }
  if (!control_fault) return;
  rapidjson::Document document;
  document.Parse(frame.payload.data(), frame.payload.size());
  if (document.HasParseError() || !document.IsObject()) {
    report(Check::safety_controller, now, state.name, "a control frame that is not a JSON object");
    return;
  }
  const auto controller = document.FindMember("controller");
  if (controller == document.MemberEnd() || controller->value.IsNull()) return;
  bool safe = controller->value.IsObject();
  if (safe) {
    const auto buttons = controller->value.FindMember("buttons");
    const auto axes = controller->value.FindMember("axes");
    safe = buttons != controller->value.MemberEnd() && buttons->value.IsObject() &&
           axes != controller->value.MemberEnd() && axes->value.IsObject();
    if (safe) {
      for (const auto& button : buttons->value.GetObject()) safe = safe && button.value.IsFalse();
      for (const auto& axis : axes->value.GetObject()) {
        const std::string_view name(axis.name.GetString(), axis.name.GetStringLength());
        const double expected = (name == "left_trigger" || name == "right_trigger") ? -1.0 : 0.0;
        safe = safe && axis.value.IsNumber() && axis.value.GetDouble() == expected;
      }
    }
  }
  if (!safe) {
    std::string faults;
    for (std::size_t f = 0; f < fault_count; ++f) {
      const auto id = static_cast<FaultId>(f);
      if (oracle_control_path(id) && state.reported_vehicle.has(id)) faults += std::string(fault_identifier(id)) + " ";
    }
    report(Check::safety_controller, now, state.name,
           "a live controller went out during a control-path fault (" +
               (faults.empty() ? std::string("NoControlMessage by the oracle's own clock") : faults.substr(0, faults.size() - 1)) + ")");
  }
}

void Oracle::on_fault(const Event& event, const FaultEvent& fault) {
  VehicleState& state = vehicle(fault.vehicle);
  if (event.component.kind == ComponentKind::player) {
    state.reported_operator.set(fault.id, fault.active);
    if (operator_) operator_->lists_changed = true;
  } else {
    state.reported_vehicle.set(fault.id, fault.active);
  }
}

void Oracle::on_connection(const Event& event, const ConnectionEvent& connection) {
  if (connection.wire == Wire::operator_ && event.component.kind == ComponentKind::player && operator_) {
    on_operator_connection(event.time - origin_, connection);
    return;
  }
  if (connection.wire != Wire::vehicle || event.component.kind != ComponentKind::streamer) return;
  VehicleState& state = vehicle(event.component.name);
  const SimTime now = event.time - origin_;
  if (connection.change == ConnectionChange::opened) {
    state.connected = true;
    state.connection_opened = now;
  } else if (connection.change == ConnectionChange::closed) {
    state.connected = false;
    state.had_close = true;
  }
}

// Conservation, message by message: a delivery or a drop of a message that is not in flight is
// a miscount. A message is in flight once for its send and once more for each copy the link
// announced (LinkOutcome::duplicated, only on a link set to duplicate); each delivery takes
// one. No rule here compares two instants, so real time judges it as virtual time does.
void Oracle::on_link(const Event& event, const LinkEvent& link) {
  VehicleState& state = vehicle(event.component.name);
  const SimTime now = event.time - origin_;
  const int route = static_cast<int>(link.route);
  LinkTally& tally = state.links[route];
  const char* way = link.route == LinkRoute::to_streamer ? "to_streamer" : "to_player";
  if (operator_ && link.route == LinkRoute::to_player && link.kind == LinkMessageKind::feedback) {
    on_feedback_link(state, link);
  }
  switch (link.outcome) {
    case LinkOutcome::sent:
      ++tally.sent;
      tally.last_sent = link.message_id;
      tally.in_flight.send(link.message_id);
      if (link.route == LinkRoute::to_streamer && link.kind == LinkMessageKind::operator_control && state.spec != nullptr &&
          state.spec->monitor) {
        report(Check::safety_monitor, now, state.name, "the Player sent control on a monitor link");
      }
      return;
    case LinkOutcome::duplicated:
      ++tally.duplicated;
      if (!tally.in_flight.contains(link.message_id)) {
        report(Check::conservation, now, state.name,
               std::string(way) + ": message " + std::to_string(link.message_id) + " duplicated but not in flight");
      } else if (!tally.duplicates_possible) {
        report(Check::conservation, now, state.name,
               std::string(way) + ": message " + std::to_string(link.message_id) + " duplicated on a link set to duplicate none");
      } else {
        tally.in_flight.duplicate(link.message_id);
      }
      return;
    case LinkOutcome::dropped:
      ++tally.dropped;
      if (!tally.in_flight.take(link.message_id) || link.message_id != tally.last_sent) {
        report(Check::conservation, now, state.name,
               std::string(way) + ": message " + std::to_string(link.message_id) + " dropped but not just sent");
      }
      return;
    case LinkOutcome::delivered:
      ++tally.delivered;
      if (!tally.in_flight.take(link.message_id)) {
        report(Check::conservation, now, state.name,
               std::string(way) + ": message " + std::to_string(link.message_id) + " delivered but not in flight");
      }
      if (link.route == LinkRoute::to_streamer && link.kind == LinkMessageKind::operator_control) {
        state.last_control_delivered = now;
      } else if (link.route == LinkRoute::to_player && link.kind == LinkMessageKind::feedback) {
        state.last_feedback_delivered = now;
      }
      return;
  }
}

// Conservation against the link's own counters: what it says it sent, delivered and dropped is
// what the oracle saw, and sent + duplicated = delivered + dropped + in flight.
void Oracle::check_counters(World& world, SimTime now) {
  for (auto& [name, state] : vehicles_) {
    if (state->spec == nullptr) continue;
    ComChannel& link = world.link(name);
    for (int route = 0; route < 2; ++route) {
      if (state->conservation_broken[route]) continue;
      const DirectionCounters& counters = (route == 0 ? link.to_streamer() : link.to_player()).counters();
      const LinkTally& tally = state->links[route];
      std::string problem;
      if (counters.sent != tally.sent || counters.delivered != tally.delivered || counters.dropped != tally.dropped ||
          counters.duplicated != tally.duplicated) {
        problem = "counters sent/delivered/dropped/duplicated " + std::to_string(counters.sent) + "/" +
                  std::to_string(counters.delivered) + "/" + std::to_string(counters.dropped) + "/" +
                  std::to_string(counters.duplicated) + ", observed " + std::to_string(tally.sent) + "/" +
                  std::to_string(tally.delivered) + "/" + std::to_string(tally.dropped) + "/" + std::to_string(tally.duplicated);
      } else if (counters.sent + counters.duplicated != counters.delivered + counters.dropped + counters.in_flight) {
        problem = "sent + duplicated (" + std::to_string(counters.sent + counters.duplicated) +
                  ") != delivered + dropped + in flight (" +
                  std::to_string(counters.delivered + counters.dropped + counters.in_flight) + ")";
      } else if (counters.in_flight < tally.in_flight.copies()) {
        problem = "in flight " + std::to_string(counters.in_flight) + " < " + std::to_string(tally.in_flight.copies()) +
                  " copies sent and neither delivered nor dropped";
      }
      if (!problem.empty()) {
        state->conservation_broken[route] = true;
        report(Check::conservation, now, name, std::string(route == 0 ? "to_streamer: " : "to_player: ") + problem);
      }
    }
  }
}

void Oracle::finish(World& world) {
  check_counters(world, world.executor().now() - origin_);
  if (operator_) check_operator_port(world.executor().now() - origin_);
  subscriptions_.clear();
  world_ = nullptr;
}

}  // namespace ocp::campaign
