#pragma once
// The facts the operator cases grade (private to the library): what the :4001 wire log shows
// per vehicle, and what reached each vehicle — the control frames on the Streamers' vehicle
// wires, watched through their event streams while a case runs.
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <functional>

#include "conformance/case.hpp"
#include "conformance/case_context.hpp"
#include "conformance/observations.hpp"
#include "conformance/streamer_host.hpp"
#include "conformance/wire_log.hpp"
#include "ocp/event_bus.hpp"

namespace ocp::conformance::detail {

struct OperatorObservations {
  // Per vehicle: the pairs the Player published (VehicleOcpShared) and the client returned.
  std::map<std::string, std::vector<SentPair>> published, returned;
  std::set<std::string> linked, monitors;  // vehicle names the Player published
  struct Sent {
    std::int64_t time_us = 0;
    std::string vehicle;
    std::string value;  // user_data (compact JSON) or active_vehicle
  };
  std::vector<Sent> active_vehicle;  // every active_vehicle the client sent
  std::vector<Sent> user_data;       // every entry's user_data
  struct GamepadSwitch {
    std::int64_t time_us = 0;
    std::string vehicle;
    std::optional<bool> disable;  // the entry's ocp_disable_gamepad; nullopt: absent
  };
  std::vector<GamepadSwitch> gamepad;  // one per client_user_data entry
  std::vector<std::int64_t> client_frames_us, opened_us, closed_us;
  std::vector<std::string> close_codes;
  std::size_t drained = 0, refused = 0;

  // Entries at or after `since_us`.
  static OperatorObservations from(const std::vector<WireLogEntry>& entries, std::int64_t since_us = 0);
  // Index in published[vehicle] of the last publication of `pair`, or -1: never published.
  std::int64_t find_published(const std::string& vehicle, const AckPair& pair) const;
  bool closed_by_peer_error() const;
};

// How a client returned one vehicle's pairs: altered = never published for that vehicle;
// stale = a newer pair had been published more than 500 ms before it came back.
struct PairReturns {
  std::size_t count = 0, stale = 0;
  std::vector<AckPair> altered;
  std::vector<AckPair> published;  // every pair published for the vehicle, for pair_diagnosis
  std::string describe(const std::string& vehicle) const;
};
PairReturns pair_returns(const OperatorObservations& observed, const std::string& vehicle);

// The setups operator cases run in: the Player with one vehicle (host_vehicle_name), or a
// fleet of two control vehicles and a monitor link, sorted first on purpose (a client that
// ignores is_monitor and takes the first name picks it).
inline constexpr const char* fleet_monitor = "monitor-0";
StreamerSetup operator_setup();
StreamerSetup fleet_setup();

// JSON text in one compact form (member order kept), so equal values compare equal as text.
std::string compact_json(std::string_view json);

// What one vehicle's Streamer sent it in each control frame.
struct ControlSeen {
  std::int64_t time_us = 0;
  bool controller_null = false;
  std::optional<std::string> user_data;  // client_user_data, compact JSON
};

// Subscribes to every control (non-monitor) vehicle's Streamer of the running World until it
// is destroyed. Bounded: a case watches a few seconds (~100 frames a second per vehicle).
class VehicleWireWatch {
 public:
  explicit VehicleWireWatch(StreamerHost& host);
  const std::vector<ControlSeen>& seen(const std::string& vehicle) const;

 private:
  static constexpr std::size_t max_per_vehicle = 20'000;
  std::map<std::string, std::vector<ControlSeen>> seen_;
  std::vector<EventBus::Subscription> subscriptions_;
};

// Hand-made VehicleOcpShared frames (operator_framing_cases.cpp), for the cases that feed the
// client frames the Player would not produce on demand.
// The Player's latest VehicleOcpShared with the hosted vehicle's pair replaced by `pair`, then
// reshaped by `shape` (may be empty); `unknown_fields` adds fields a later product may add.
std::string shared_frame(CaseContext& context, const AckPair& pair, const std::function<void(VehicleOcpShared&)>& shape,
                         bool unknown_fields);
// Connected, settled, and the Player's own output paused; false (and `outcome` set) if not.
bool ready_for_crafted(CaseContext& context, Outcome& outcome);
// Hand-made frames listing the vehicles in another order every other frame: each control
// vehicle's own pair must come back under its name (operator_key_order.cpp).
Outcome grade_reordered_vehicles(CaseContext& context);
// Connection kept since `start_us`, every pair in `required` returned, none never published.
Outcome grade_crafted_shared(CaseContext& context, std::int64_t start_us, const std::vector<AckPair>& sent,
                             const std::vector<AckPair>& required, const std::string& what);

}  // namespace ocp::conformance::detail
