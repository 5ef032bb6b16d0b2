#pragma once
// The link's events (what happened to one message on one direction of the com channel, and a
// change of its impairments), apart from events.hpp so that every unit that sees the event
// stream does not compile the impairment model: ImpairmentChange names Impairments only
// through a pointer, and only its readers include ocp/impairments.hpp.
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace ocp {

struct Impairments;  // ocp/impairments.hpp (target ocp_link)

// What happened to one message on one direction of the fake com channel.
enum class LinkRoute : std::uint8_t { to_streamer, to_player };
enum class LinkMessageKind : std::uint8_t { operator_control, feedback, video_frame, ping, pong };
// duplicated: at send time, a second copy of the message was put in flight (it repeats the
// message_id); each copy is delivered, or dropped with the link's queue, on its own. Judges
// count copies by this event, never by the time between two deliveries: in real time the two
// copies' timers fire microseconds apart.
enum class LinkOutcome : std::uint8_t { sent, delivered, dropped, duplicated };
// in_flight_limit: the direction already held LinkDirection::in_flight_limit() messages.
enum class DropReason : std::uint8_t { none, random_loss, burst_loss, outage, queue_full, recorded_loss, in_flight_limit };
struct LinkEvent {
  LinkRoute route = LinkRoute::to_streamer;
  LinkOutcome outcome = LinkOutcome::sent;
  LinkMessageKind kind = LinkMessageKind::operator_control;
  DropReason reason = DropReason::none;  // dropped: why
  std::size_t size_bytes = 0;
  std::uint64_t message_id = 0;          // per direction, in send order; a duplicate repeats it
};

struct ImpairmentChange {
  LinkRoute route = LinkRoute::to_streamer;
  const Impairments* impairments = nullptr;  // the new settings
};

// Stable lower-case names, used by the JSON Lines trace and reports.
std::string_view link_route_name(LinkRoute route);
std::string_view link_message_kind_name(LinkMessageKind kind);
std::string_view link_outcome_name(LinkOutcome outcome);
std::string_view drop_reason_name(DropReason reason);

}  // namespace ocp
