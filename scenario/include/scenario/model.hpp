#pragma once
// The scenario model: what a scenario file says, after parsing and validation (parse.hpp).
// Everything here is already checked: vehicle and camera names exist, times are ordered,
// expectations refer to events that exist. The runner (runner.hpp) never re-validates.
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "ocp/client_source.hpp"
#include "ocp/events.hpp"
#include "ocp/faults.hpp"
#include "ocp/impairments.hpp"
#include "ocp/time.hpp"
#include "player/gamepad.hpp"
#include "world/world.hpp"

namespace ocp::scenario {

// Where something was written: 1-based line and column in the scenario file.
struct Mark {
  int line = 0;
  int column = 0;
};

// Impairment fields a file sets; the rest keep their current value.
struct ImpairmentPatch {
  std::optional<Micros> delay, jitter, reorder_extra_delay;
  std::optional<Impairments::JitterKind> jitter_kind;
  std::optional<double> loss, duplicate, reorder, bandwidth_bps;
  std::optional<double> good_to_bad, bad_to_good, loss_in_good, loss_in_bad;
  std::optional<bool> burst_loss, down;
  std::optional<std::size_t> queue_limit_bytes, queue_limit_packets;
  std::optional<std::shared_ptr<const DeliveryTrace>> trace;
  std::optional<std::shared_ptr<const LinkRecording>> replay;
};
Impairments apply_patch(Impairments base, const ImpairmentPatch& patch);
// Linear interpolation of the numeric fields (delay, jitter, probabilities, bandwidth) at
// fraction f ∈ [0, 1]; the switches (burst_loss, down, jitter kind) take `to`'s value.
Impairments interpolate(const Impairments& from, const Impairments& to, double fraction);

enum class Direction { both, to_streamer, to_player };

struct GamepadScriptSetting {
  enum class Kind { idle, drive, constant, waveform } kind = Kind::idle;
  Controller constant;
  Waveform waveform;
};

// --- timeline actions -------------------------------------------------------------------
struct SetImpairments {
  std::string vehicle;
  Direction direction = Direction::both;
  ImpairmentPatch patch;
  Micros ramp{0};   // > 0: move linearly from the current settings to the patched ones
};
struct LinkOutage {
  std::string vehicle;
  Direction direction = Direction::both;
  Micros duration{0};
};
struct CameraStall {
  std::string vehicle;
  std::string camera;
  bool stalled = true;
  Micros duration{0};   // > 0: unstall again after this long
};
struct FrameLoopStall {
  std::string vehicle;
  Micros duration{0};
};
struct ControlThreadStall {
  std::string vehicle;
  Micros duration{0};
};
// An in-process client drops its connection (client side). A vehicle without one (an external
// client) is closed from the Streamer's side instead. listener_down > 0: a restart of the
// Streamer's vehicle listener: the Streamer closes the connection and its port refuses new
// ones for that long, whichever the client (World::close_vehicle_connection).
struct DisconnectVehicle {
  std::string vehicle;
  Micros listener_down{0};
};
inline constexpr Micros max_listener_down{60'000'000};
// Replaces an in-process vehicle client's misbehaviours from now on (all off = well-behaved).
struct SetMisbehaviour {
  std::string vehicle;
  Misbehaviour misbehave;
  // Once, at this event: a second vehicle connection to the Streamer while the client's is
  // open (SPEC §3.1: accepted and closed at once); it sends nothing and stays open this side.
  bool second_connection = false;
};
// The in-process operator client's misbehaviours on the Player's :4001 port (SPEC §2, §4.2),
// replaced as a whole by each operator_misbehave event (all off = well-behaved). Each broken
// frame takes the place of a keep-alive, so it goes out at the keep-alive period.
enum class BadClientMessage {
  none,
  not_an_object,   // a JSON array → the Player closes (not_an_object)
  wrong_type,      // active_vehicle as a number → the Player closes (wrong_type)
  eof_mid_frame,   // half a frame, then the client hangs up → the Player closes (truncated_frame)
};
std::string_view bad_client_message_name(BadClientMessage kind);
struct OperatorMisbehaviour {
  bool silent = false;            // no keep-alives → the Player's read timeout closes (SPEC §2)
  bool malformed_json = false;    // keep-alives are not JSON → the Player closes (malformed_json)
  bool oversized_frames = false;  // keep-alives are > 16 KiB frames → drained, connection kept
  BadClientMessage bad_message = BadClientMessage::none;
  bool any() const { return silent || malformed_json || oversized_frames || bad_message != BadClientMessage::none; }
};
struct SetOperatorMisbehaviour {   // names no vehicle: the :4001 port is the Player's
  OperatorMisbehaviour misbehave;
  // Once, at this event: a second :4001 connection while the client's is open (SPEC §4.2:
  // one client at a time, the newcomer is refused); it sends nothing and stays open this side.
  bool second_connection = false;
};
struct GamepadAction {
  enum class Kind { unplug, replug, script } kind = Kind::unplug;
  GamepadScriptSetting script;
};
struct SelectVehicle {
  std::optional<std::string> vehicle;   // nullopt: clear the selection
};
// Client data from a second source (web view / plugin / tcp), once or repeatedly.
struct ClientDataAction {
  enum class Echo { none, latest, corrupt };   // the returned pair a plugin/tcp source puts in
  struct Entry {
    std::optional<std::string> user_data_json;
    std::optional<bool> disable_gamepad;
    Echo echo = Echo::none;
  };
  ClientSource source = ClientSource::plugin;
  std::optional<std::string> active_vehicle;
  std::map<std::string, Entry> vehicles;
  Micros every{0};            // > 0: repeat at this period …
  std::optional<SimTime> until;   // … until this time (default: the end of the run)
};

using Action = std::variant<SetImpairments, LinkOutage, CameraStall, FrameLoopStall,
                            ControlThreadStall, DisconnectVehicle, SetMisbehaviour, GamepadAction,
                            SelectVehicle, ClientDataAction, SetOperatorMisbehaviour>;

struct TimelineEvent {
  SimTime at{0};
  std::string name;     // optional; expectations refer to events by name
  std::string label;    // what happened, for reports ("impairments truck-1 both")
  Mark mark;
  Action action;
};

// --- expectations -----------------------------------------------------------------------
// A fault's first raise (or clear) edge at or after `after` must come within [min, max].
struct FaultEdgeExpectation {
  FaultId fault = FaultId::HighLatency;
  std::string vehicle;
  bool raised = true;   // false: cleared
  SimTime after{0};
  std::string after_label;   // the event name or the time as written
  Micros min{0}, max{0};
};
struct FaultNeverExpectation {
  FaultId fault = FaultId::InvalidMac;
  std::optional<std::string> vehicle;   // nullopt: on no vehicle
  SimTime from{0};   // raises before this are not counted (start-up: no pair to echo yet)
  std::optional<SimTime> until;   // nullopt: to the end of the run; activity from here on is not counted
};
// The fault stays active on one vehicle through [from, until] (nullopt: to the end of the run):
// one interval covers the whole window.
struct FaultAlwaysExpectation {
  FaultId fault = FaultId::NoControlMessage;
  std::string vehicle;
  SimTime from{0};
  std::string from_label;   // the event name or the time as written
  std::optional<SimTime> until;
  std::string until_label;
};
// The fault's state at one instant on named vehicles (or every control vehicle but the
// active one, which must then not have it).
struct FaultStateExpectation {
  FaultId fault = FaultId::VehicleControlInactive;
  SimTime at{0};
  std::vector<std::string> active_on, inactive_on;
  bool every_vehicle_but_active = false;
};
struct ThresholdExpectation {
  std::string metric;                   // latency_ms, echo_delay_ms, …
  std::optional<std::string> vehicle;   // nullopt: all vehicles together
  std::string aggregate;                // avg min max med count rate p(N)
  double percentile = 0.0;              // for p(N)
  std::string op;                       // < <= > >= == !=
  double value = 0.0;
  std::string text;                     // as written, "p(99) < 150"
};
enum class Invariant { default_controller_during_control_fault, no_stale_pair_after_reconnect };
struct InvariantExpectation {
  Invariant invariant = Invariant::default_controller_during_control_fault;
};

// One controller field (an axis or a button, by its recording-format name) and the value it
// must carry: "right_trigger=0.4", "a=1".
struct ControllerFieldValue {
  std::string name;
  double value = 0.0;
};

// What reached a vehicle: within `within` after `after`, a control frame to it must carry this
// controller state and / or this client user data (operator commands through user data).
// `every`: every control frame in the window must (and at least one must be sent), so that
// "no frame in the window with X" can be said.
struct DeliveryExpectation {
  enum class ControllerState { any, null, default_, driving, safe /* null or default */ };
  std::string vehicle;
  SimTime after{0};
  std::string after_label;
  Micros within{0};
  bool every = false;
  ControllerState controller = ControllerState::any;
  std::optional<std::string> user_data_json;   // compared as JSON values
  bool user_data_absent = false;               // the frame carries no client_user_data
  std::vector<ControllerFieldValue> fields;    // a controller with these values (not null)
};

// Rare events on the stream that say what the operator side and the connections did: a
// client-data source locked (SPEC §4.3), a second source in conflict with it, a connection
// closed (with its reason) or refused (a second connection, SPEC §3.1).
enum class NotableKind { source_locked, source_conflict, connection_closed, connection_refused };
std::string_view notable_kind_name(NotableKind kind);

// Such an event must happen in [from, until] (written `after` + `within`), or, with `never`,
// must not (written `never: true` with an optional `from` / `until`).
struct EventExpectation {
  NotableKind kind = NotableKind::source_conflict;
  bool never = false;
  std::optional<std::string> vehicle;    // connection events: that vehicle's wire (nullopt: any)
  Wire wire = Wire::vehicle;             // connection events: vehicle or operator wire
  std::optional<ClientSource> source;    // source_locked: the source; source_conflict: the offending one
  std::optional<ClientSource> locked;    // source_conflict: the locked one
  std::string reason;                    // connection events: text the close reason must contain
  SimTime from{0};
  std::string from_label;
  std::optional<SimTime> until;          // nullopt: the end of the run (never only)
  Micros min{0};                         // after / within [min, max]: not before from + min
};

// What the operator client read in the Player's VehicleOcpShared (SPEC §4.1) about one
// vehicle: one field's value (a dotted path into the vehicle's entry, e.g.
// vehicle_data.user_data.mode, missing_cameras.0) or a whole fault list (sender_fault,
// receiver_fault: compared as sets, the order is not promised). The value counted at an
// instant is the one in the last frame the client had read by then.
struct FeedbackCheck {
  std::string field;           // the path as written
  std::string expected_json;   // equals: the JSON value; a fault list: a JSON array of identifiers
  bool as_set = false;         // a fault list
};
// Every check holds at `from` and at every frame read until `until` (nullopt: the end of the
// run); `instant` (written `at`): from == until.
struct FeedbackExpectation {
  std::string vehicle;
  std::vector<FeedbackCheck> checks;
  SimTime from{0};
  std::string from_label;
  std::optional<SimTime> until;
  std::string until_label;
  bool instant = false;
};

// The world must refuse to start, with a reason containing this text (a configuration the
// simulator rejects, written down as a regression test instead of an error).
struct RefusesToStartExpectation {
  std::string reason;
};

using ExpectationKind = std::variant<FaultEdgeExpectation, FaultNeverExpectation, FaultAlwaysExpectation,
                                     FaultStateExpectation, ThresholdExpectation, InvariantExpectation,
                                     DeliveryExpectation, RefusesToStartExpectation, EventExpectation,
                                     FeedbackExpectation>;
struct Expectation {
  std::string title;   // one line, as printed in the verdict list
  Mark mark;
  ExpectationKind kind;
};

// An in-process operator client on the Player's :4001 side (scenario/src/operator_client.cpp):
// it reads every VehicleOcpShared and sends ClientOcpShared keep-alives (SPEC §4.2), so the
// operator side is on the event stream. Off by default: no client, as before.
struct OperatorClientSetting {
  bool connect = false;
  Micros keep_alive_period{1'000'000};   // SPEC §4.2: "about once a second"; < the 2 s read timeout
  Micros reconnect_backoff{1'000'000};   // after the Player closed the connection
  Micros pipe_delay{0};                  // one way, each direction
};

struct Scenario {
  std::string path;
  std::string name;          // the file's stem
  std::string description;
  std::uint64_t seed = 1;
  SimTime duration{0};
  WorldConfig world;         // vehicles, links, timers, misbehaviours (seed set by the runner)
  OperatorClientSetting operator_client;
  GamepadScriptSetting gamepad;
  std::vector<TimelineEvent> timeline;   // ordered by `at`
  std::vector<Expectation> expectations;
  // "file:line:column: text" for what the file may say but probably did not mean (client data
  // for a vehicle the world does not have: the Player warns and ignores it, SPEC §4.2).
  std::vector<std::string> warnings;
};

std::string_view invariant_name(Invariant invariant);
std::string_view direction_name(Direction direction);

}  // namespace ocp::scenario
