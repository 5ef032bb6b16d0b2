#pragma once
// The safety report (docs/conformance.md, "Safety report"; issue #26): nothing on the TCP wire
// shows a vehicle's own safety logic (SPEC §10) unless the client says what it applied. A
// client that puts these five fields into vehicle_user_data.user_data of its responses gets
// the vehicle/10/* cases graded:
//   safe_state   bool     the output is the vehicle's safe state
//   drive_state  string   "enabled" or "disabled" (the drive interlock)
//   throttle     number   applied throttle, 0..1
//   brake        number   applied brake, 0..1
//   steer        number   applied steering, -1..1 (a fraction of the maximum angle)
// The reference vehicle client sends them in every response (vehicle_client/core/user_data.cpp).
// A response without all five carries no report; a client none of whose responses carries one
// is "not judged" on §10 (INFORMATIONAL, never a failure): the report is opt-in.
//
// The cases play scripts of hand-made control frames (send_crafted: the Streamer's own output
// paused) and read the reports that came back during each phase (private to the library).
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "case_helpers.hpp"

namespace ocp::conformance::detail {

struct SafetyReport {
  std::int64_t time_us = 0;
  bool safe_state = false;
  bool enabled = false;  // drive_state "enabled"
  double throttle = 0.0;
  double brake = 0.0;
  double steer = 0.0;
};

// The report in one response payload; nullopt with `problem` set to what is missing.
std::optional<SafetyReport> read_safety_report(std::string_view payload, std::int64_t time_us, std::string& problem);
// "safe_state false, drive_state enabled, throttle 0.500, brake 0.000, steer 0.000"
std::string describe_report(const SafetyReport& report);

// One step of a script: `frames` control frames 10 ms apart, each like `control` (its own pair).
struct SafetyPhase {
  std::size_t frames = 0;
  CraftedControl control;
};

struct ScriptRun {
  std::vector<std::int64_t> phase_start_us;  // per phase: its first frame written (end_us if none was)
  std::int64_t last_frame_us = 0;            // the last frame of the script written
  std::int64_t end_us = 0;                   // the end of the silence after it
  std::vector<SafetyReport> reports;         // from the first phase on, in arrival order
  std::size_t responses = 0;                 // responses in that time (in the case's window)
  std::string missing;                       // why the first of them carried no report
};

// Plays the phases, then `silence` without any frame (the connection stays open), and reads
// every report of the responses from the first phase on. `salt` makes the pairs the case's own.
ScriptRun play_safety_script(CaseContext& context, std::uint64_t salt, const std::vector<SafetyPhase>& phases,
                             milliseconds silence);

// Adds the reports of the responses (in the case's window) from `from_us` on to `run`.
void collect_safety_reports(const Observations& observed, std::int64_t from_us, ScriptRun& run);
// No response of `run` carried a report: the case is not judged (the one-line reason).
std::optional<Outcome> safety_not_judged(const ScriptRun& run);
// Every case starts so: the client connected, 200 ms of the Streamer's own control. The outcome
// to return at once when the client did not connect, or answered without a report (so a client
// that does not report costs each case 200 ms, not a whole script); nullopt: play the script.
std::optional<Outcome> safety_prologue(CaseContext& context);

// Does the rule hold from `from_us` + `bound_us` to `to_us`? The client has `bound_us` to get
// there; from then on every report must keep it.
struct Settling {
  std::optional<std::int64_t> reached_after_us;  // first report keeping the rule, after from_us
  std::size_t checked = 0;                       // reports from from_us + bound_us to to_us
  std::optional<SafetyReport> broken;            // the first of them that breaks the rule
  bool holds() const { return checked > 0 && !broken; }
};
Settling settle_within(const ScriptRun& run, std::int64_t from_us, std::int64_t to_us, std::int64_t bound_us,
                       const std::function<bool(const SafetyReport&)>& rule);
// "safe state after 305 ms, kept in 42 reports" or what broke it, for the case's actual text.
std::string describe_settling(const Settling& settling, std::int64_t from_us, const std::string& what);

// The last report before `time_us`, if any.
std::optional<SafetyReport> last_report_before(const ScriptRun& run, std::int64_t time_us);

// Control frames the scripts are made of (raw gamepad values: triggers -1 released .. 1 full).
CraftedControl pad_frame(const CraftedPad& pad, bool fault = false);
// Release every button, then press the interlock's enable button with the sticks at rest (start:
// the reference client's enable, safety_layer.hpp), then `drive` frames at half throttle.
std::vector<SafetyPhase> enable_and_drive(std::size_t drive, const InterlockButtons& interlock);
// A pad that presses `button` (by name) with the sticks at rest and the triggers as given.
CraftedPad pad_pressing(const std::string& button, double right_trigger = -1.0);

inline bool in_safe_state(const SafetyReport& r) { return r.safe_state && r.throttle == 0.0; }
inline bool disabled_and_still(const SafetyReport& r) { return !r.enabled && r.throttle == 0.0; }
inline bool driving(const SafetyReport& r) { return !r.safe_state && r.enabled && r.throttle > 0.0; }

}  // namespace ocp::conformance::detail
