#pragma once
// Observer: the one subscriber a scenario run adds to World::events(). It turns the event
// stream into what verdicts and reports need — fault intervals, measured series, message
// counts and safety-invariant violations — and nothing else: control payloads are decoded
// only while a control-path fault is active and only when an invariant asks for it, so a
// run stays close to the world's own speed.
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ocp/event_bus.hpp"
#include "ocp/faults.hpp"
#include "ocp/time.hpp"
#include "scenario/model.hpp"
#include "scenario/series.hpp"
#include "world/world.hpp"

namespace ocp::scenario {

struct Interval {
  SimTime start{0};
  std::optional<SimTime> end;   // nullopt: still active when the run ended
  bool operator==(const Interval&) const = default;
};

struct RouteCounters {
  std::uint64_t sent = 0, delivered = 0, dropped = 0, duplicated = 0;
};

// One link direction over time, for the report's plot (link_series.cpp): per 100 ms bucket
// with deliveries, the delivered throughput and the highest queueing delay (one-way delay
// less the set propagation delay); empty buckets between deliveries read 0 Mbit/s.
struct LinkSeries {
  PlotSeries throughput_mbps;
  PlotSeries queueing_delay_ms;
};

// Every series is bounded (series.hpp): a run of hours keeps what a run of minutes does.
struct VehicleObservations {
  Series latency_ms;      // per Streamer control tick with a valid pair
  Series echo_delay_ms;   // control frame out → the response echoing its pair in
  Series control_gap_ms;  // between consecutive control frames to the vehicle
  Series feedback_gap_ms; // between consecutive feedback deliveries at the Player
  RouteCounters to_streamer, to_player;
  LinkSeries to_streamer_link, to_player_link;   // only when the run observes link events
  // The Player's ping_latency_ms, sampled every 100 ms by the runner (not an event: for the
  // report's plot only, never for a verdict).
  Series ping_ms;
  std::uint64_t connections_opened = 0;
  std::uint64_t control_frames_checked = 0;   // decoded while a control-path fault was active
};

struct Violation {
  SimTime time{0};
  std::string vehicle;
  std::string detail;
};

// A control frame decoded inside a delivery window (DeliveryExpectation).
struct Delivery {
  SimTime time{0};
  std::string vehicle;
  enum class Controller { null, default_, driving } controller = Controller::null;
  std::optional<ocp::Controller> controller_value;   // the decoded state, unless null
  std::optional<std::string> user_data_json;
};

// A notable event (EventExpectation): rare, so every one is kept.
struct NotableEvent {
  SimTime time{0};
  NotableKind kind = NotableKind::source_locked;
  std::string component;   // the vehicle (Streamer events) or the Player's name
  Wire wire = Wire::vehicle;
  ClientSource source = ClientSource::tcp;   // locked: the source; conflict: the offending one
  ClientSource locked = ClientSource::tcp;   // conflict: the locked one
  std::string reason;                        // connection events: the close reason
};

// One field of a vehicle's entry in the Player's VehicleOcpShared (FeedbackExpectation).
struct FeedbackWatch {
  std::string vehicle;
  std::string field;   // dotted path: vehicle_data.user_data.mode, receiver_fault
};
// That field over the run, as the operator client was sent it: one value per change.
struct FeedbackValue {
  SimTime time{0};
  std::string json;   // compact JSON; "" when the field (or the vehicle's entry) was absent
};
struct FeedbackSeries {
  std::vector<FeedbackValue> changes;   // the first frame's value, then every change
  std::uint64_t frames = 0;             // VehicleOcpShared frames looked at
  bool truncated = false;               // more changes than kept (feedback_change_limit)
};
inline constexpr std::size_t violations_kept = 64;
// Control frames decoded in delivery windows: 11 minutes of 100 Hz; a longer window is judged
// on its first frames, and the verdict says so.
inline constexpr std::size_t delivery_limit = 65536;
// Changes kept per watched field: a field that changes every frame (ping_latency_ms at 100 Hz)
// fills it in ~10 minutes; the verdict then says it stopped looking.
inline constexpr std::size_t feedback_change_limit = 65536;
// The key of a watched field in Observations::feedback.
std::string feedback_key(std::string_view vehicle, std::string_view field);

struct DeliveryWindow {
  std::string vehicle;
  SimTime start{0}, end{0};
};

struct Observations {
  std::map<std::string, VehicleObservations, std::less<>> vehicles;
  // (vehicle, fault) → intervals in time order; both sides (the fault id says which).
  std::map<std::pair<std::string, FaultId>, std::vector<Interval>> faults;
  std::vector<std::pair<SimTime, std::optional<std::string>>> active_vehicle;   // changes
  // Invariant violations: every one counted, the first violations_kept of each kept.
  std::vector<Violation> controller_violations;   // non-default controller under a control-path fault
  std::vector<Violation> stale_pair_violations;   // old pair echoed on a new connection
  std::uint64_t controller_violation_count = 0, stale_pair_violation_count = 0;
  std::vector<Delivery> deliveries;               // decoded inside delivery windows only, at most delivery_limit
  bool deliveries_truncated = false;              // more frames in windows than kept
  std::vector<NotableEvent> notable_events;       // source locks and conflicts, closes, refusals
  std::map<std::string, FeedbackSeries, std::less<>> feedback;   // feedback_key → the watched field
  std::uint64_t reconnects = 0;                   // vehicle connections opened after a close
  std::uint64_t events = 0;
};

struct ObserverOptions {
  bool check_controllers = false;   // decode control frames under control-path faults
  // LinkEvents (feedback gaps, losses) are the most frequent events: a World builds them only
  // while somebody listens to a link's bus, so the Observer listens only when asked to.
  bool link_events = true;
  std::vector<DeliveryWindow> delivery_windows;   // decode control frames to these vehicles then
  std::vector<FeedbackWatch> feedback_watches;    // decode VehicleOcpShared frames for these
};

class Observer {
  // One subscriber, every event once: see attach_parts().
 public:
  // Listens to `world.events()` from now on (construct before World::start() to see the very
  // first events) …
  Observer(World& world, ObserverOptions options);
  // Listens to one bus only (tests publishing a hand-made stream); attach_parts does nothing.
  Observer(EventBus& bus, ObserverOptions options);
  ~Observer();
  Observer(const Observer&) = delete;
  Observer& operator=(const Observer&) = delete;

  // … and, called right after start() (no event can happen in between in virtual time), moves
  // to the Player's, Streamers' and (with link_events) links' own buses, so that the events
  // nobody needs are never built.
  void attach_parts();
  // Times are kept relative to this instant (real-time runs: the executor's clock at start).
  void set_origin(SimTime origin) { origin_ = origin; }

  const Observations& observations() const { return observations_; }
  Observations& observations() { return observations_; }

 private:
  struct VehicleState;
  void on_event(const Event& event);
  // on_event's steps, one per kind of event it looks at.
  void on_link(std::string_view name, const LinkEvent& link, SimTime now);
  void on_control_out(std::string_view name, VehicleState& vehicle, const WireFrame& frame, SimTime now);
  void record_delivery(std::string_view name, const WireFrame& frame, SimTime now);
  void check_controller(std::string_view name, VehicleState& vehicle, const WireFrame& frame, SimTime now);
  void on_response_in(std::string_view name, VehicleState& vehicle, const WireFrame& frame, SimTime now);
  void on_fault(const FaultEvent& fault, SimTime now);
  void on_vehicle_connection(std::string_view name, const ConnectionEvent& connection);
  void record_notable(const Event& event, SimTime now);
  void on_feedback_frame(const WireFrame& frame, SimTime now);   // observer_feedback.cpp
  VehicleState& state(std::string_view vehicle);

  ObserverOptions options_;
  Observations observations_;
  std::map<std::string, std::unique_ptr<VehicleState>, std::less<>> states_;
  World* world_ = nullptr;
  SimTime origin_{0};
  std::vector<EventBus::Subscription> subscriptions_;
};

}  // namespace ocp::scenario
