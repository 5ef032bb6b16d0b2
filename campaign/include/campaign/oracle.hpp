#pragma once
// The oracle (docs/campaigns.md): an independent judge of one running world. It subscribes to
// the World's event stream (ocp/events.hpp) and checks, while the world runs, what SPEC says
// must hold — computing every condition itself from what it observes and from the world's
// model (its timers and timeline). It shares no code with the cores: an oracle that did would
// share their bugs. Its only other look at the world is the links' public counters, for
// conservation.
//
//   Oracle oracle(scenario);
//   RunOptions options; options.on_built = [&](World& w) { oracle.attach(w); };
//   options.on_finished = [&](World& w) { oracle.finish(w); };
//   run_scenario(scenario, options);   … oracle.violations() …
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "ocp/event_bus.hpp"
#include "scenario/model.hpp"

namespace ocp::campaign {

// The invariant families, as named in reports, summary.json and shrinking ("the same invariant").
enum class Check {
  safety_controller,   // a control frame during a control-path fault carried a live controller
  safety_monitor,      // a monitor link was sent control
  safety_frame_size,   // a frame above 16 KiB was written
  fault_model,         // a §6 fault active when its condition does not hold, or the reverse
  latency_loop,        // a latency sample that no echoed pair explains, or an older pair accepted
  stale_pair,          // a pair from before a reconnect echoed on the new connection
  liveness,            // after the last disturbance, a fault did not clear or the loop did not close
  conservation,        // sent ≠ delivered + lost + in flight on a link direction
  determinism,         // the same world twice, two different traces
  // The Player's :4001 port, in worlds with an operator client (oracle_operator.cpp):
  operator_port,       // a broken frame kept, a close nothing explains, a late read timeout, two clients
  operator_feedback,   // VehicleOcpShared's fault lists differ from the faults the cores reported
  // An external vehicle client (ocp_campaign run --client), judged from the Streamer's side
  // by ClientWatch (client_watch.hpp), not by the Oracle:
  client_echo,         // an echo that is not byte-exact, or not the current pair
  client_reconnect,    // no new connection within the bound after the Streamer closed one
  client_alive,        // the client process exited or crashed during the world
};
inline constexpr int check_count = 14;
std::string_view check_name(Check check);
// Why `check` is not judged in a campaign of this kind ("not judged in real time"), or "" when
// it is. `client_worlds`: --client worlds (no operator client, one run of the client per
// world); `client_real_time`: with --time real (the oracle's timing checks off).
std::string_view not_judged_because(Check check, bool client_worlds, bool client_real_time);

struct Violation {
  Check check = Check::fault_model;
  SimTime at{0};          // from the world's start
  std::string vehicle;    // may be empty
  std::string detail;     // one line
  // For fault_model: the fault, and whether it should have been active (the shrinker writes
  // this as a fault-state expectation).
  std::optional<FaultId> fault;
  bool should_be_active = false;
  // The scenario expectation that fails the same way, where the oracle can state one (the
  // shrinker writes it into the regression file).
  std::optional<scenario::ExpectationKind> regression;
};

// Tolerances of the fault model, stated (docs/campaigns.md). In virtual time every threshold is
// checked at the Streamer's control tick where it is due, exactly; what the oracle cannot
// observe directly gets the smallest window that covers it.
struct OracleTolerances {
  Micros player_frame{10'000};   // the Player evaluates its faults once a frame
  // Real time (ocp_campaign --client): what a time observed on the event stream may differ from
  // the instant the core acted on it (0 in virtual time, where both are the same instant).
  Micros real_time_slack{0};
  // The fault model, liveness and which pair a latency sample came from hold to the tick in
  // virtual time. In real time a loaded machine runs frame loops, ticks and writes late, and
  // the simulator then truly raises CameraLost or NoFeedbackMessage for its own lateness: not
  // a finding about the client, and judged exactly by virtual-time campaigns instead.
  bool judge_timing = true;
};
// The slack of a real-time world: a loaded 2-core machine runs a tick or a write tens of ms late.
inline constexpr Micros real_time_oracle_slack{50'000};

class SourceLockWatch;   // oracle_source_lock.hpp

class Oracle {
 public:
  explicit Oracle(const scenario::Scenario& scenario, OracleTolerances tolerances = {});
  ~Oracle();
  Oracle(const Oracle&) = delete;
  Oracle& operator=(const Oracle&) = delete;

  // Subscribes to the world's events (before it starts) and remembers its links for counters.
  void attach(World& world);
  // End-of-run checks (conservation against the links' counters); call before the world stops.
  void finish(World& world);

  const std::vector<Violation>& violations() const { return violations_; }
  std::uint64_t violation_count() const { return violation_count_; }   // also those not kept
  std::uint64_t events_seen() const { return events_; }
  bool liveness_checked() const { return liveness_checked_; }

 private:
  struct VehicleState;
  struct LinkTally;
  struct OperatorPort;
  void on_event(const Event& event);
  void on_wire_frame(const Event& event, const WireFrame& frame);
  void on_fault(const Event& event, const FaultEvent& fault);
  void on_connection(const Event& event, const ConnectionEvent& connection);
  void on_latency_sample(const Event& event, const LatencySample& sample);
  void on_link(const Event& event, const LinkEvent& link);
  // The operator port (oracle_operator.cpp).
  void on_operator_connection(SimTime now, const ConnectionEvent& connection);
  void on_operator_frame(SimTime now, const WireFrame& frame);
  void on_source_locked(SimTime now, const SourceLocked& locked);
  void judge_tcp_lock(SimTime now);
  void on_feedback_link(VehicleState& vehicle, const LinkEvent& link);
  void check_operator_port(SimTime now);
  void check_feedback_lists(SimTime now, std::string_view payload);
  void check_operator_liveness(SimTime now);
  void check_fault_model(VehicleState& vehicle, SimTime now, const LatencySample& sample);
  void check_operator_faults(VehicleState& vehicle, SimTime now);
  void check_liveness(VehicleState& vehicle, SimTime now, const LatencySample& sample);
  void check_controller(VehicleState& vehicle, SimTime now, const WireFrame& frame);
  void check_counters(World& world, SimTime now);
  void report(Check check, SimTime now, const std::string& vehicle, std::string detail,
              std::optional<FaultId> fault = std::nullopt, bool should_be_active = false,
              std::optional<scenario::ExpectationKind> regression = std::nullopt);
  VehicleState& vehicle(std::string_view name);

  const scenario::Scenario& scenario_;
  OracleTolerances tolerances_;
  World* world_ = nullptr;
  SimTime origin_{0};
  SimTime liveness_at_{0};
  bool liveness_possible_ = false;
  bool liveness_checked_ = false;
  bool source_locked_ = false;      // a client-data source took the loop over (§4.3)
  bool source_conflict_ = false;
  std::optional<std::string> selected_;   // the active vehicle, as the Player announced it
  SimTime selected_since_{0};
  bool gamepad_plugged_ = true;
  std::map<std::string, std::unique_ptr<VehicleState>, std::less<>> vehicles_;
  std::unique_ptr<OperatorPort> operator_;   // null: the world connects no operator client
  std::unique_ptr<SourceLockWatch> source_lock_watch_;   // the locked tcp client left: no pair
  std::vector<EventBus::Subscription> subscriptions_;
  std::vector<Violation> violations_;
  std::uint64_t violation_count_ = 0;
  std::uint64_t events_ = 0;
};

}  // namespace ocp::campaign
