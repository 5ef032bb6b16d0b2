// Stable names of the event vocabulary (events.hpp, client_source.hpp). They appear in the
// JSON Lines trace (docs/trace-format.md): renaming one is a trace format change.
#include "ocp/events.hpp"

namespace ocp {

std::string_view client_source_name(ClientSource source) {
  switch (source) {
    case ClientSource::tcp: return "tcp";
    case ClientSource::webview: return "webview";
    case ClientSource::plugin: return "plugin";
  }
  return "?";
}

std::string_view component_kind_name(ComponentKind kind) {
  switch (kind) {
    case ComponentKind::world: return "world";
    case ComponentKind::streamer: return "streamer";
    case ComponentKind::player: return "player";
    case ComponentKind::link: return "link";
    case ComponentKind::vehicle_client: return "vehicle_client";
  }
  return "?";
}

std::string_view wire_name(Wire wire) { return wire == Wire::vehicle ? "vehicle" : "operator"; }

std::string_view frame_direction_name(FrameDirection direction) {
  return direction == FrameDirection::out ? "out" : "in";
}

std::string_view wire_message_kind_name(WireMessageKind kind) {
  switch (kind) {
    case WireMessageKind::control: return "control";
    case WireMessageKind::vehicle_response: return "vehicle_response";
    case WireMessageKind::vehicle_ocp_shared: return "vehicle_ocp_shared";
    case WireMessageKind::client_ocp_shared: return "client_ocp_shared";
  }
  return "?";
}

std::string_view fault_side_name(FaultSide side) {
  return side == FaultSide::vehicle ? "vehicle" : "operator";
}

std::string_view connection_change_name(ConnectionChange change) {
  switch (change) {
    case ConnectionChange::opened: return "opened";
    case ConnectionChange::closed: return "closed";
    case ConnectionChange::refused: return "refused";
  }
  return "?";
}

std::string_view link_route_name(LinkRoute route) {
  return route == LinkRoute::to_streamer ? "to_streamer" : "to_player";
}

std::string_view link_message_kind_name(LinkMessageKind kind) {
  switch (kind) {
    case LinkMessageKind::operator_control: return "operator_control";
    case LinkMessageKind::feedback: return "feedback";
    case LinkMessageKind::video_frame: return "video_frame";
    case LinkMessageKind::ping: return "ping";
    case LinkMessageKind::pong: return "pong";
  }
  return "?";
}

std::string_view link_outcome_name(LinkOutcome outcome) {
  switch (outcome) {
    case LinkOutcome::sent: return "sent";
    case LinkOutcome::delivered: return "delivered";
    case LinkOutcome::dropped: return "dropped";
    case LinkOutcome::duplicated: return "duplicated";
  }
  return "?";
}

std::string_view drop_reason_name(DropReason reason) {
  switch (reason) {
    case DropReason::none: return "none";
    case DropReason::random_loss: return "random_loss";
    case DropReason::burst_loss: return "burst_loss";
    case DropReason::outage: return "outage";
    case DropReason::queue_full: return "queue_full";
    case DropReason::recorded_loss: return "recorded_loss";
    case DropReason::in_flight_limit: return "in_flight_limit";
  }
  return "?";
}

}  // namespace ocp
