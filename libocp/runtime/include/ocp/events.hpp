#pragma once
// The one event stream (issue: every tool observes the same things). Every component —
// Streamer, Player, each link direction, the World — publishes typed events of this small
// set on its EventBus (event_bus.hpp); scenario verdicts, conformance wire logs, the loop
// benchmark, the trace and the dashboard subscribe to what they need, without hooks in a core.
//
// An Event is a value that lives only during the call that delivers it: string views and
// pointers inside it (payload bytes, peer names, a close reason) point into the publisher's
// state. A subscriber that keeps something copies it.
//
// Times are the executor's: virtual µs in virtual time, µs since the process started in real
// time. The JSON Lines form of every event (field names, units) is in docs/trace-format.md.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>
#include <variant>

#include "ocp/client_source.hpp"
#include "ocp/error.hpp"
#include "ocp/faults.hpp"
#include "ocp/link_events.hpp"
#include "ocp/messages.hpp"
#include "ocp/pair_diagnosis.hpp"
#include "ocp/time.hpp"

namespace ocp {

// Who published an event.
enum class ComponentKind : std::uint8_t { world, streamer, player, link, vehicle_client };
struct Component {
  ComponentKind kind = ComponentKind::world;
  std::string_view name;  // streamer, link, vehicle_client: the vehicle; player: the Player's name
};

// The two TCP APIs.
enum class Wire : std::uint8_t {
  vehicle,   // Streamer ⇄ vehicle client (:4000)
  operator_, // Player ⇄ operator client (:4001)
};
enum class FrameDirection : std::uint8_t { out, in };  // as seen by the publisher
enum class WireMessageKind : std::uint8_t {
  control,             // OcpControlMessage, Streamer → vehicle
  vehicle_response,    // VehicleResponseMessage, vehicle → Streamer
  vehicle_ocp_shared,  // VehicleOcpShared, Player → operator client
  client_ocp_shared,   // ClientOcpShared, operator client → Player
};

// One frame written to or read from a byte stream.
struct WireFrame {
  Wire wire = Wire::vehicle;
  FrameDirection direction = FrameDirection::out;
  WireMessageKind kind = WireMessageKind::control;
  std::uint32_t length_prefix = 0;  // as on the wire
  std::string_view payload;         // the payload bytes; empty for a drained oversized frame
  bool drained = false;             // inbound frame over the limit: read and discarded
  std::optional<AckPair> ack;       // the pair a control message or a vehicle response carries
  std::string_view peer;
};

// A fault raised or cleared. side = fault_side(id): vehicle (receiver) or operator_station (sender).
struct FaultEvent {
  FaultSide side = FaultSide::vehicle;
  FaultId id = FaultId::VehicleNoResponse;
  bool active = false;
  std::string_view vehicle;  // the vehicle it concerns
};

enum class ConnectionChange : std::uint8_t {
  opened,
  closed,
  refused,  // a second connection while one is active (SPEC §3.1): accepted and closed at once
};
struct ConnectionEvent {
  Wire wire = Wire::vehicle;
  ConnectionChange change = ConnectionChange::opened;
  std::string_view peer;
  const CloseReason* reason = nullptr;  // closed and refused: why; opened: null
};

// Published by a Streamer at every control tick, whether or not a vehicle is connected.
struct LatencySample {
  std::optional<std::uint64_t> latency_ms;  // now − ack_time of the newest valid pair (SPEC §5.7)
  std::optional<Micros> pair_age;           // now − arrival of that pair back at the Streamer
  Micros tick_lateness{0};                  // how late the tick ran after its deadline
  bool control_sent = false;                // a control frame went to a connected vehicle
};

struct GamepadChange {
  bool plugged = true;
};

struct SourceLocked {
  ClientSource source = ClientSource::tcp;
};
struct SourceConflict {
  ClientSource locked = ClientSource::tcp;
  ClientSource offending = ClientSource::tcp;
};

struct ActiveVehicleChange {
  std::optional<std::string_view> vehicle;  // nullopt: no vehicle receives gamepad input
};

// Published by a Streamer at the first rejected returned pair (InvalidMac) of an episode: an
// episode lasts until a valid pair is accepted again, so a client that alters every pair gives
// one of these, not 100 a second. Missing pairs are not judged: they have nothing to compare.
struct PairRejected {
  AckPair rejected;
  PairJudgement judgement;   // the cause and the nearest pair this Streamer issued
  std::string_view hint;     // describe_rejected_pair(): one line for a log, a status line, a page
};

using EventBody = std::variant<WireFrame, FaultEvent, ConnectionEvent, LatencySample, LinkEvent,
                               ImpairmentChange, GamepadChange, SourceLocked, SourceConflict,
                               ActiveVehicleChange, PairRejected>;

struct Event {
  SimTime time{0};
  Component component;
  EventBody body;
};

// Stable lower-case names, used by the JSON Lines trace and reports.
std::string_view component_kind_name(ComponentKind kind);
std::string_view wire_name(Wire wire);                          // "vehicle" | "operator"
std::string_view frame_direction_name(FrameDirection direction); // "out" | "in"
std::string_view wire_message_kind_name(WireMessageKind kind);
std::string_view fault_side_name(FaultSide side);  // "vehicle" | "operator"
std::string_view connection_change_name(ConnectionChange change);

}  // namespace ocp
