// `ocp_conformance operator`, the client's data: user_data reaching the vehicle,
// ocp_disable_gamepad, and active_vehicle with several vehicles and a monitor link
// (SPEC §4.2, §4.4, §7). What reached a vehicle is read off its Streamer's vehicle wire
// (VehicleWireWatch, from the event stream).
#include <fmt/ranges.h>

#include <set>

#include "case_helpers.hpp"
#include "conformance/vehicle_cases.hpp"
#include "operator_observations.hpp"

namespace ocp::conformance {
namespace {

using namespace detail;

// Control frames take a Player frame, the link and a Streamer tick to reach the vehicle.
constexpr std::int64_t settle_us = 100'000;

Outcome user_data_reaches_vehicle(CaseContext& context) {
  const VehicleWireWatch watch(context.host());
  context.run_for(milliseconds(1000));
  const OperatorObservations observed = OperatorObservations::from(context.entries());
  if (observed.user_data.empty()) {
    return informational("the client sent no user_data in 1 s: nothing to check");
  }
  std::map<std::string, std::set<std::string>> sent;  // per vehicle: every value sent
  for (const auto& u : observed.user_data) {
    if (!observed.linked.contains(u.vehicle)) {
      return failed(fmt::format(
          "user_data sent for '{}', which is not a linked vehicle (the Player links: {}): it reaches no vehicle",
          u.vehicle, fmt::join(observed.linked, ", ")));
    }
    sent[u.vehicle].insert(u.value);
  }
  std::string actual;
  for (const auto& [vehicle, values] : sent) {
    if (observed.monitors.contains(vehicle)) continue;  // a monitor link is sent no control at all
    std::size_t carried = 0, matching = 0;
    for (const ControlSeen& c : watch.seen(vehicle)) {
      if (!c.user_data) continue;
      ++carried;
      if (values.contains(*c.user_data)) {
        ++matching;
      } else {
        return failed(fmt::format("'{}' received client_user_data the client never sent it: {}", vehicle,
                                  c.user_data->substr(0, 200)));
      }
    }
    const std::string counts = fmt::format("'{}': {} distinct user_data values sent, {} control frames carried one",
                                           vehicle, values.size(), matching);
    if (matching == 0) return failed(counts + "; the client's user_data never reached the vehicle");
    actual += (actual.empty() ? "" : "; ") + counts;
  }
  return ok(actual + "; every one unchanged");
}

Outcome disable_gamepad(CaseContext& context) {
  const VehicleWireWatch watch(context.host());
  context.run_for(milliseconds(1000));
  const OperatorObservations observed = OperatorObservations::from(context.entries());
  const std::string vehicle = host_vehicle_name;
  std::optional<std::int64_t> disabled_at, enabled_at;  // first true; first explicit false after it
  std::size_t entries = 0, omitted = 0;
  for (const auto& g : observed.gamepad) {
    if (g.vehicle != vehicle) continue;
    if (!disabled_at) {
      if (g.disable == true) disabled_at = g.time_us;
      continue;
    }
    if (enabled_at) break;
    ++entries;
    if (g.disable == false) enabled_at = g.time_us;
    omitted += !g.disable.has_value();
  }
  if (!disabled_at)
    return informational("the client never set ocp_disable_gamepad: the gamepad drives the vehicle; nothing to check");
  std::size_t frames = 0, with_controller = 0;
  for (const ControlSeen& c : watch.seen(vehicle)) {
    if (c.time_us < *disabled_at + settle_us || (enabled_at && c.time_us >= *enabled_at)) continue;
    ++frames;
    with_controller += !c.controller_null;
  }
  const std::string counts = fmt::format(
      "the client disabled the gamepad; {} later entries, {} without ocp_disable_gamepad; "
      "{} of {} control frames after it carried a controller",
      entries, omitted, with_controller, frames);
  if (frames == 0) return failed(counts + "; no control frame reached the vehicle");
  if (with_controller > 0) return failed(counts + " (an entry without ocp_disable_gamepad turns the gamepad back on)");
  return ok(counts);
}

Outcome selects_active_vehicle(CaseContext& context) {
  context.run_for(milliseconds(1000));
  const OperatorObservations observed = OperatorObservations::from(context.entries());
  const std::size_t control = observed.linked.size() - observed.monitors.size();
  const std::string linked = fmt::format("{} vehicles linked ({} control, monitor: {})", observed.linked.size(),
                                         control, fmt::join(observed.monitors, ", "));
  if (observed.active_vehicle.empty()) {
    return failed(
        fmt::format("{}; no active_vehicle in {} client frames: no vehicle receives gamepad input, every one raises "
                    "VehicleControlInactive",
                    linked, observed.client_frames_us.size()));
  }
  std::set<std::string> chosen;
  for (const auto& a : observed.active_vehicle) {
    if (observed.monitors.contains(a.value))
      return failed(
          fmt::format("{}; active_vehicle '{}' is a monitor link (watch-only, sent no control)", linked, a.value));
    if (!observed.linked.contains(a.value))
      return failed(fmt::format("{}; active_vehicle '{}' is not a linked vehicle", linked, a.value));
    chosen.insert(a.value);
  }
  return ok(fmt::format("{}; active_vehicle {} in {} of {} client frames", linked, fmt::join(chosen, ", "),
                        observed.active_vehicle.size(), observed.client_frames_us.size()));
}

}  // namespace

void add_operator_data_cases(std::vector<VehicleCase>& cases) {
  cases.push_back(
      {{{"operator/4.2/5",
         "user_data reaches its vehicle unchanged",
         "SPEC §4.2, seed 004",
         "\"client_user_data maps vehicle name → entry … Unknown vehicle names: ignored with a warning.\" — "
         "\"user_data "
         "reaches that vehicle as client_user_data in its control messages.\"",
         Tier::must,
         milliseconds(10'000),
         {"OK: every user_data is keyed by a linked vehicle and reaches that vehicle's control messages unchanged "
          "(two control vehicles and a monitor linked)",
          "INFORMATIONAL: the client sends no user_data (nothing to check)"},
         "broken_client.py op-wrong-name"},
        user_data_reaches_vehicle},
       fleet_setup()});
  cases.push_back(
      {{{"operator/4.4/1",
         "ocp_disable_gamepad keeps the gamepad off the vehicle",
         "SPEC §4.4, §3.2, seed 003",
         "\"This can be disabled by setting ocp_disable_gamepad: true in the data sent back to OCP\" — \"controller is "
         "null "
         "when the operator disabled gamepad forwarding\"; the Player applies each entry as the vehicle's whole client "
         "state (player_core.hpp), so an entry without it turns the gamepad back on",
         Tier::must,
         milliseconds(10'000),
         {"OK: once the client sets ocp_disable_gamepad: true, every later control frame carries controller null until "
          "it sends false",
          "INFORMATIONAL: the client never sets ocp_disable_gamepad (nothing to check)"},
         "broken_client.py op-disable-once (op-disable passes)"},
        disable_gamepad},
       operator_setup()});
  cases.push_back(
      {{{"operator/7/1",
         "with several vehicles, active_vehicle names a control vehicle, never a monitor",
         "SPEC §7, seed 004",
         "\"With multiple vehicles this must be set — if it is not set, no vehicle will receive gamepad input and all "
         "vehicles "
         "will raise the VehicleControlInactive fault.\" — \"A monitor link receives feedback and video but sends no "
         "control; is_monitor: true.\"",
         Tier::must,
         milliseconds(10'000),
         {"OK: with two control vehicles and a monitor linked, the client sends active_vehicle, and every value names "
          "a "
          "linked vehicle that is not a monitor"},
         "broken_client.py op-no-active (or op-monitor-active)"},
        selects_active_vehicle},
       fleet_setup()});
}

}  // namespace ocp::conformance
