// The vehicle's own safety logic (SPEC §10, seed 000 "Handle faults safely"), graded from the
// safety report the client puts in its responses (safety_report.hpp): command timeout,
// actuator limits, drive interlock and emergency stop, fault → safe state. OCP is transport,
// not the safety controller, so these are SHOULD; a client that does not report is not judged.
// A client that reports and breaks the rule outright (keeps driving) is FAILED, not NON-STRICT:
// there is no "works, but not the preferred way" in a vehicle that ignores a fault.
#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

#include "conformance/vehicle_cases.hpp"
#include "safety_report.hpp"

namespace ocp::conformance {
namespace {

using namespace detail;

// Command timeout: NoControlMessage fires after 1 s without operator commands (SPEC §8), and
// from then on OCP itself sends the safe default. A vehicle's own watchdog must be no slower
// than that, or a silent Streamer leaves it driving on the last command longer than OCP would
// (the reference client's watchdog is 300 ms: 700 ms to spare on a loaded machine).
constexpr std::int64_t safety_timeout_bound_us = 1'000'000;
// The silence watched: past the bound, below the reference client's 2 s server-silence limit
// (after which it closes the connection and reconnects).
constexpr milliseconds safety_silence{1300};
// Fault → safe state and the emergency stop: within the Streamer's latency_limit (500 ms, SPEC
// §8), the delay past which OCP itself calls the control path faulty. The reference client
// acts at its next model step (10 ms).
constexpr std::int64_t safety_react_bound_us = 500'000;

std::string safety_ms(std::int64_t us) { return fmt::format("{:.0f} ms", static_cast<double>(us) / 1000.0); }

// The client must be driving before the watchdog or a fault can show anything.
std::optional<Outcome> not_driving(const ScriptRun& run, std::int64_t at_us, const std::string& when,
                                   const InterlockButtons& interlock) {
  const auto before = last_report_before(run, at_us);
  if (before && driving(*before)) return std::nullopt;
  return informational(
      fmt::format("not judged: the client was not driving {} ({}) after a press of '{}' with the "
                  "sticks at rest and half throttle: nothing to see (a client that enables with another "
                  "button: --enable-button NAME --stop-button NAME)",
                  when, before ? describe_report(*before) : std::string("no report"), interlock.enable));
}

Outcome command_timeout(CaseContext& context) {
  if (auto early = safety_prologue(context)) return *early;
  const ScriptRun run = play_safety_script(context, 101, enable_and_drive(30, context.interlock()), safety_silence);
  if (auto not_judged = safety_not_judged(run)) return *not_judged;
  if (auto idle = not_driving(run, run.last_frame_us, "when the control messages stopped", context.interlock()))
    return *idle;
  const Settling settled = settle_within(run, run.last_frame_us, run.end_us, safety_timeout_bound_us, in_safe_state);
  const std::string counts = fmt::format("driving, then no control message for {} (connection open): {}",
                                         safety_ms(run.end_us - run.last_frame_us),
                                         describe_settling(settled, run.last_frame_us, "safe state with throttle 0"));
  if (settled.checked == 0)
    return informational("not judged: no response after the 1 s bound (vehicle/2/7's business); " + counts);
  if (!settled.holds()) return failed(counts + " (no command timeout: still driving on the last command)");
  return ok(counts);
}

// Every report in range: throttle and brake 0..1, steer -1..1.
std::optional<SafetyReport> first_out_of_range(const ScriptRun& run) {
  for (const SafetyReport& r : run.reports) {
    if (r.throttle < 0.0 || r.throttle > 1.0 || r.brake < 0.0 || r.brake > 1.0 || r.steer < -1.0 || r.steer > 1.0)
      return r;
  }
  return std::nullopt;
}

CraftedControl user_data_command(std::string json) {
  CraftedControl control;
  control.controller = CraftedController::null;
  control.client_user_data = std::move(json);
  return control;
}

Outcome actuator_limits(CaseContext& context) {
  if (auto early = safety_prologue(context)) return *early;
  std::vector<SafetyPhase> phases = enable_and_drive(10, context.interlock());
  phases.push_back({30, pad_frame(CraftedPad{.left_x = -1.0, .right_trigger = 1.0})});  // full throttle, full left
  phases.push_back({20, pad_frame(CraftedPad{.left_x = 1.0, .left_trigger = 1.0})});    // full brake, full right
  // Commands beyond the limits, for a client that takes them from client_user_data (SPEC §3.2).
  phases.push_back({5, user_data_command(R"({"throttle":0,"enable":true})")});
  phases.push_back({30, user_data_command(R"({"throttle":5,"brake":-3,"steer":-9,"enable":true})")});
  phases.push_back({20, user_data_command(R"({"throttle":-4,"brake":7,"steer":9,"enable":true})")});
  const ScriptRun run = play_safety_script(context, 102, phases, milliseconds(100));
  if (auto not_judged = safety_not_judged(run)) return *not_judged;
  double throttle = 0.0, steer = 0.0;
  for (const SafetyReport& r : run.reports) {
    throttle = std::max(throttle, std::abs(r.throttle));
    steer = std::max(steer, std::abs(r.steer));
  }
  const std::string counts = fmt::format(
      "{} reports during full-scale gamepad steps and user-data commands of throttle 5, brake -3, "
      "steer -9 (and -4, 7, 9); largest |throttle| {:.3f}, |steer| {:.3f}",
      run.reports.size(), throttle, steer);
  if (const auto out = first_out_of_range(run)) {
    return failed(fmt::format("{}; at +{} the report says {} (outside throttle/brake 0..1, steer -1..1)", counts,
                              safety_ms(out->time_us - run.phase_start_us.front()), describe_report(*out)));
  }
  if (throttle == 0.0 && steer == 0.0)
    return informational("not judged: no actuator moved (" + counts + "): no limit to see");
  return ok(counts + "; every one within the limits");
}

// How vehicle/10/3 and vehicle/10/4 judge their scripts: the client, driving when the first
// cause comes, reaches `rule` within the latency_limit after each of two causes and keeps it
// while the cause lasts (the first until `first_until_phase` starts, the second to the end).
struct TwoReactions {
  std::string driving_when;  // the first cause, for not_driving: "when the fault came"
  std::size_t first_phase = 0, first_until_phase = 0, second_phase = 0;
  std::string first_label, second_label;  // each cause in the actual text
  std::string wanted;                     // the rule in words: "safe state with throttle 0"
  std::function<bool(const SafetyReport&)> rule;
};

// `prefix`: what the case judged before, for the actual text; `failure_hint`: added to it when failed.
Outcome judge_two_reactions(const ScriptRun& run, const InterlockButtons& interlock, const TwoReactions& check,
                            const std::string& prefix, const std::string& failure_hint) {
  const auto& start = run.phase_start_us;
  if (auto idle = not_driving(run, start[check.first_phase], check.driving_when, interlock)) return *idle;
  const Settling first =
      settle_within(run, start[check.first_phase], start[check.first_until_phase], safety_react_bound_us, check.rule);
  const Settling second = settle_within(run, start[check.second_phase], run.end_us, safety_react_bound_us, check.rule);
  const std::string counts = fmt::format(
      "{}{}: {}; {}: {}", prefix, check.first_label, describe_settling(first, start[check.first_phase], check.wanted),
      check.second_label, describe_settling(second, start[check.second_phase], check.wanted));
  if (!first.holds() || !second.holds()) return failed(counts + failure_hint);
  return ok(counts);
}

// Interlock phases: full throttle never enabled; enable and drive; emergency stop (back) and
// throttle after it; enable and drive; a fault and throttle after it.
std::vector<SafetyPhase> interlock_script(const InterlockButtons& interlock) {
  std::vector<SafetyPhase> phases{{30, pad_frame(CraftedPad{.right_trigger = 1.0})}};
  const auto enable = enable_and_drive(30, interlock);
  phases.insert(phases.end(), enable.begin(), enable.end());
  phases.push_back({30, pad_frame(pad_pressing(interlock.stop, 0.0))});
  phases.push_back({30, pad_frame(CraftedPad{.right_trigger = 0.0})});
  phases.insert(phases.end(), enable.begin(), enable.end());
  CraftedControl fault;
  fault.controller = CraftedController::safe_default;
  fault.fault = true;
  fault.fault_reason = "No Control Message";
  phases.push_back({30, fault});
  phases.push_back({30, pad_frame(CraftedPad{.right_trigger = 0.0})});
  return phases;
}
constexpr std::size_t interlock_stop_phase = 4, interlock_after_stop_phase = 5, interlock_fault_phase = 9;

Outcome drive_interlocks(CaseContext& context) {
  if (auto early = safety_prologue(context)) return *early;
  const ScriptRun run = play_safety_script(context, 103, interlock_script(context.interlock()), milliseconds(50));
  if (auto not_judged = safety_not_judged(run)) return *not_judged;
  const auto& start = run.phase_start_us;
  const Settling never_enabled = settle_within(run, start[0], start[1], 0, disabled_and_still);
  const std::string first =
      "full throttle before any enable: " + describe_settling(never_enabled, start[0], "disabled with throttle 0");
  if (!never_enabled.holds())
    return failed(first + (never_enabled.broken ? " (no interlock: it drives without being enabled)" : ""));
  const TwoReactions check{
      .driving_when = "before the emergency stop",
      .first_phase = interlock_stop_phase,
      .first_until_phase = interlock_after_stop_phase + 1,
      .second_phase = interlock_fault_phase,
      .first_label = "stop button '" + context.interlock().stop + "', then throttle without enable",
      .second_label = "fault, then throttle without enable",
      .wanted = "disabled with throttle 0",
      .rule = disabled_and_still};
  return judge_two_reactions(run, context.interlock(), check, first + "; ", "");
}

// Fault phases: the default controller with fault true (a control-path fault), and the
// operator's controller passed through with fault true (a camera lost: SPEC §3.2, §6).
std::vector<SafetyPhase> fault_script(const InterlockButtons& interlock) {
  std::vector<SafetyPhase> phases = enable_and_drive(30, interlock);
  CraftedControl path_fault;
  path_fault.controller = CraftedController::safe_default;
  path_fault.fault = true;
  path_fault.fault_reason = "No Control Message, Latency Loop Not Closed";
  phases.push_back({60, path_fault});
  const auto again = enable_and_drive(30, interlock);
  phases.insert(phases.end(), again.begin(), again.end());
  CraftedControl camera_lost = pad_frame(CraftedPad{.right_trigger = 0.0}, true);
  camera_lost.fault_reason = "Camera Lost";
  camera_lost.missing_cameras = R"(["front"])";
  phases.push_back({60, camera_lost});
  return phases;
}
constexpr std::size_t fault_default_phase = 3, fault_passed_through_phase = 7;

Outcome fault_safe_state(CaseContext& context) {
  if (auto early = safety_prologue(context)) return *early;
  const ScriptRun run = play_safety_script(context, 104, fault_script(context.interlock()), milliseconds(50));
  if (auto not_judged = safety_not_judged(run)) return *not_judged;
  const TwoReactions check{.driving_when = "when the fault came",
                           .first_phase = fault_default_phase,
                           .first_until_phase = fault_default_phase + 1,
                           .second_phase = fault_passed_through_phase,
                           .first_label = "fault with the default controller",
                           .second_label = "fault with the controller passed through (camera lost)",
                           .wanted = "safe state with throttle 0",
                           .rule = in_safe_state};
  return judge_two_reactions(run, context.interlock(), check, "",
                             " (telemetry.fault must bring the safe state, whatever the controller says)");
}

const std::string safety_source = "SPEC §10, seed 000 (safety; Handle faults safely)";
const std::string safety_not_judged_line =
    "INFORMATIONAL: not judged — the client reports no safety state (docs/conformance.md, Safety report), or did not "
    "drive when enabled";

}  // namespace

void add_safety_cases(std::vector<VehicleCase>& cases) {
  cases.push_back({{{"vehicle/10/1",
                     "command timeout: no control message → safe state within 1 s",
                     safety_source,
                     "\"The vehicle integration should still enforce … command timeouts\" — \"Use telemetry.fault and "
                     "your own watchdogs to "
                     "decide when to hold, coast, brake, or otherwise enter a vehicle-specific safe state.\"",
                     Tier::should,
                     milliseconds(10'000),
                     {"OK: enabled and driving, then control messages stop (connection open, 1.3 s): the report shows "
                      "safe_state true "
                      "with throttle 0 within 1 s (NoControlMessage's bound, SPEC §8) and keeps it",
                      "FAILED: still driving 1 s after the last control message", safety_not_judged_line},
                     "broken_client.py no-watchdog (FAILED); vehicle_client --watchdog-ms 1500 (FAILED)"},
                    command_timeout},
                   {}});
  cases.push_back(
      {{{"vehicle/10/2",
         "actuator limits: commands beyond them never reach the actuators",
         safety_source,
         "\"The vehicle integration should still enforce actuator limits\" — axes are raw gamepad values in -1.0..1.0",
         Tier::should,
         milliseconds(10'000),
         {"OK: over full-scale gamepad steps and user-data commands of throttle 5, brake -3, steer -9 (and -4, 7, 9), "
          "every "
          "report keeps throttle and brake in 0..1 and steer in -1..1",
          "FAILED: a report outside those limits", safety_not_judged_line},
         "broken_client.py no-limits (FAILED)"},
        actuator_limits},
       {}});
  cases.push_back(
      {{{"vehicle/10/3",
         "drive interlock and emergency stop: no driving until enabled; back and faults disable",
         safety_source,
         "\"The vehicle integration should still enforce … drive-state interlocks, emergency stop behavior\"",
         Tier::should,
         milliseconds(10'000),
         {"OK: full throttle on a new connection leaves drive_state disabled and throttle 0; after an enable (start "
          "pressed "
          "with the sticks at rest), the back button and then a fault each disable within 500 ms, and throttle without "
          "a new "
          "enable stays at 0",
          "FAILED: it drives without an enable, or stays enabled after the back button or a fault",
          safety_not_judged_line},
         "broken_client.py no-interlock (FAILED)"},
        drive_interlocks},
       {}});
  cases.push_back(
      {{{"vehicle/10/4",
         "telemetry.fault → safe state, whatever the controller says",
         safety_source,
         "\"Use telemetry.fault and your own watchdogs to decide when to hold, coast, brake, or otherwise enter a "
         "vehicle-specific safe state. Do not rely only on the controller values\"",
         Tier::should,
         milliseconds(10'000),
         {"OK: driving, then fault true with the default controller, and (enabled again) fault true with the "
          "operator's "
          "controller passed through (a camera lost): each time safe_state true with throttle 0 within 500 ms (the "
          "latency_limit), kept while the fault lasts",
          "FAILED: no safe state, or throttle, while telemetry.fault is true", safety_not_judged_line},
         "broken_client.py ignore-fault (FAILED)"},
        fault_safe_state},
       {}});
}

}  // namespace ocp::conformance
