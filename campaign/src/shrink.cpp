// Shrinking (shrink.hpp): greedy, one-change-at-a-time reduction. Each pass tries the biggest
// cuts first (half the timeline, then single events), and passes repeat until nothing more
// can go or the run budget is spent.
#include "campaign/shrink.hpp"

#include <algorithm>

#include "campaign/world_check.hpp"
#include "scenario/write.hpp"

namespace ocp::campaign {

namespace {

using namespace scenario;

bool mentions(const Action& action, const std::string& vehicle) {
  return std::visit(
      [&](const auto& a) -> bool {
        using T = std::decay_t<decltype(a)>;
        if constexpr (std::is_same_v<T, GamepadAction> || std::is_same_v<T, SetOperatorMisbehaviour>) {
          return false;   // the gamepad and the :4001 port are the Player's, no vehicle's
        } else if constexpr (std::is_same_v<T, SelectVehicle>) {
          return a.vehicle == vehicle;
        } else if constexpr (std::is_same_v<T, ClientDataAction>) {
          return a.active_vehicle == vehicle || a.vehicles.count(vehicle) > 0;
        } else {
          return a.vehicle == vehicle;
        }
      },
      action);
}

Scenario without_vehicle(const Scenario& in, std::size_t index) {
  Scenario out = in;
  const std::string name = out.world.vehicles[index].name;
  out.world.vehicles.erase(out.world.vehicles.begin() + static_cast<std::ptrdiff_t>(index));
  out.world.player.fleet = out.world.vehicles.size() > 1;
  std::erase_if(out.timeline, [&](const TimelineEvent& event) { return mentions(event.action, name); });
  return out;
}

class Shrinker {
 public:
  Shrinker(const ShrinkTarget& target, int max_runs, const WorldChecker& check)
      : target_(target), max_runs_(max_runs), check_(check) {}

  // Runs the candidate; keeps it when it still fails the same way.
  bool still_fails(const Scenario& candidate) {
    if (runs_ >= max_runs_) return false;
    ++runs_;
    const WorldOutcome outcome = check_ ? check_(candidate) : check_world(candidate, {target_.check == Check::determinism});
    for (const Violation& violation : outcome.violations) {
      if (target_.matches(violation)) {
        last_ = violation;
        return true;
      }
    }
    return false;
  }

  ShrinkResult run(Scenario current) {
    if (!still_fails(current)) return {current, {}, runs_};
    Violation found = last_;
    bool progress = true;
    while (progress && runs_ < max_runs_) {
      progress = false;
      // Vehicles (never the last one).
      for (std::size_t v = current.world.vehicles.size(); v-- > 0 && current.world.vehicles.size() > 1;) {
        if (Scenario candidate = without_vehicle(current, v); still_fails(candidate)) {
          current = std::move(candidate);
          found = last_;
          progress = true;
        }
      }
      // Timeline: chunks from half the timeline down to single events.
      for (std::size_t chunk = std::max<std::size_t>(1, current.timeline.size() / 2); chunk >= 1; chunk /= 2) {
        for (std::size_t start = 0; start < current.timeline.size();) {
          Scenario candidate = current;
          const auto first = candidate.timeline.begin() + static_cast<std::ptrdiff_t>(start);
          candidate.timeline.erase(first, first + static_cast<std::ptrdiff_t>(std::min(chunk, candidate.timeline.size() - start)));
          if (still_fails(candidate)) {
            current = std::move(candidate);
            found = last_;
            progress = true;
          } else {
            start += chunk;
          }
        }
        if (chunk == 1) break;
      }
      // The operator client, once no timeline event needs it.
      if (current.operator_client.connect &&
          std::none_of(current.timeline.begin(), current.timeline.end(), [](const TimelineEvent& event) {
            return std::holds_alternative<SetOperatorMisbehaviour>(event.action);
          })) {
        Scenario candidate = current;
        candidate.operator_client = OperatorClientSetting{};
        if (still_fails(candidate)) {
          current = std::move(candidate);
          found = last_;
          progress = true;
        }
      }
      // Start impairments back to a clean link.
      for (std::size_t v = 0; v < current.world.vehicles.size(); ++v) {
        Scenario candidate = current;
        candidate.world.vehicles[v].to_streamer = Impairments{};
        candidate.world.vehicles[v].to_player = Impairments{};
        if (!(candidate.world.vehicles[v].to_streamer.delay == current.world.vehicles[v].to_streamer.delay &&
              candidate.world.vehicles[v].to_player.delay == current.world.vehicles[v].to_player.delay &&
              current.world.vehicles[v].to_streamer.loss_probability == 0 &&
              current.world.vehicles[v].to_player.loss_probability == 0 &&
              current.world.vehicles[v].to_streamer.jitter == Micros{0} &&
              current.world.vehicles[v].to_player.jitter == Micros{0}) &&
            still_fails(candidate)) {
          current = std::move(candidate);
          found = last_;
          progress = true;
        }
      }
      // Duration: just past the violation (whole 100 ms), never before the last event.
      SimTime last_event{0};
      for (const TimelineEvent& event : current.timeline) last_event = std::max(last_event, event.at);
      const SimTime shorter{std::max(last_event.count(), ((found.at.count() + 100'000) / 100'000) * 100'000)};
      if (shorter < current.duration) {
        Scenario candidate = current;
        candidate.duration = shorter;
        if (still_fails(candidate)) {
          current = std::move(candidate);
          found = last_;
          progress = true;
        }
      }
    }
    return {current, found, runs_};
  }

 private:
  ShrinkTarget target_;
  int max_runs_;
  WorldChecker check_;
  int runs_ = 0;
  Violation last_;
};

}  // namespace

ShrinkResult shrink(const Scenario& failing, const ShrinkTarget& target, int max_runs, const WorldChecker& check) {
  return Shrinker(target, max_runs, check).run(failing);
}

std::string regression_yaml(const ShrinkResult& shrunk, const std::string& repro_command) {
  Scenario scenario = shrunk.scenario;
  const Violation& v = shrunk.violation;
  scenario.expectations.clear();
  if (v.check == Check::fault_model && v.fault && !v.vehicle.empty()) {
    FaultStateExpectation state;
    state.fault = *v.fault;
    state.at = v.at;
    (v.should_be_active ? state.active_on : state.inactive_on).push_back(v.vehicle);
    scenario.expectations.push_back({"", {}, state});
  } else if (v.regression) {
    scenario.expectations.push_back({"", {}, *v.regression});
  } else if (v.check == Check::stale_pair) {
    scenario.expectations.push_back({"", {}, InvariantExpectation{Invariant::no_stale_pair_after_reconnect}});
  } else {
    // The scenario format has no expectation for this family (yet): the file states the one
    // that comes closest, and the header names the oracle check that must pass.
    scenario.expectations.push_back({"", {}, InvariantExpectation{Invariant::default_controller_during_control_fault}});
  }
  std::string header = "Shrunk by ocp_campaign from a failing world (" + std::to_string(shrunk.runs) + " runs).\n";
  header += "Invariant: " + std::string(check_name(v.check)) + "\n";
  header += "At " + duration_text(v.at) + (v.vehicle.empty() ? "" : " on " + v.vehicle) + ": " + v.detail + "\n";
  header += "Reproduce: " + repro_command + "\n";
  return write_scenario_yaml(scenario, header);
}

}  // namespace ocp::campaign
