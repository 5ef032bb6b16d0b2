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
};
inline constexpr int check_count = 9;
std::string_view check_name(Check check);

struct Violation {
  Check check = Check::fault_model;
  SimTime at{0};          // from the world's start
  std::string vehicle;    // may be empty
  std::string detail;     // one line
  // For fault_model: the fault, and whether it should have been active (the shrinker writes
  // this as a fault-state expectation).
  std::optional<FaultId> fault;
  bool should_be_active = false;
};

// Tolerances of the fault model, stated (docs/campaigns.md). In virtual time every threshold is
// checked at the Streamer's control tick where it is due, exactly; what the oracle cannot
// observe directly gets the smallest window that covers it.
struct OracleTolerances {
  Micros player_frame{10'000};   // the Player evaluates its faults once a frame
};

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
  void on_event(const Event& event);
  void on_wire_frame(const Event& event, const WireFrame& frame);
  void on_fault(const Event& event, const FaultEvent& fault);
  void on_connection(const Event& event, const ConnectionEvent& connection);
  void on_latency_sample(const Event& event, const LatencySample& sample);
  void on_link(const Event& event, const LinkEvent& link);
  void check_fault_model(VehicleState& vehicle, SimTime now, const LatencySample& sample);
  void check_operator_faults(VehicleState& vehicle, SimTime now);
  void check_liveness(VehicleState& vehicle, SimTime now, const LatencySample& sample);
  void check_controller(VehicleState& vehicle, SimTime now, const WireFrame& frame);
  void check_counters(World& world, SimTime now);
  void report(Check check, SimTime now, const std::string& vehicle, std::string detail,
              std::optional<FaultId> fault = std::nullopt, bool should_be_active = false);
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
  std::vector<EventBus::Subscription> subscriptions_;
  std::vector<Violation> violations_;
  std::uint64_t violation_count_ = 0;
  std::uint64_t events_ = 0;
};

}  // namespace ocp::campaign
