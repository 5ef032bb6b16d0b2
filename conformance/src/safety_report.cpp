#include "safety_report.hpp"

#include <rapidjson/document.h>

namespace ocp::conformance::detail {
namespace {

// A number field of the report, or a problem.
bool safety_number_field(const rapidjson::Value& user, const char* key, double& value, std::string& problem) {
  const auto it = user.FindMember(key);
  if (it == user.MemberEnd() || !it->value.IsNumber()) {
    problem = fmt::format("user_data has no number {}", key);
    return false;
  }
  value = it->value.GetDouble();
  return true;
}

std::optional<SafetyReport> no_safety_report(std::string& problem, std::string why) {
  problem = std::move(why);
  return std::nullopt;
}

// The time the harness wrote `pair`, or -1: never written (the connection had closed).
std::int64_t safety_sent_time(const Observations& observed, const AckPair& pair) {
  const std::int64_t index = observed.find_sent(pair);
  return index < 0 ? -1 : observed.sent[static_cast<std::size_t>(index)].time_us;
}

// The frame index `i` of a script belongs to this phase.
std::size_t safety_phase_of(const std::vector<SafetyPhase>& phases, std::size_t i) {
  std::size_t phase = 0;
  while (phase + 1 < phases.size() && i >= phases[phase].frames) i -= phases[phase++].frames;
  return phase;
}

}  // namespace

std::optional<SafetyReport> read_safety_report(std::string_view payload, std::int64_t time_us, std::string& problem) {
  rapidjson::Document doc;
  doc.Parse(payload.data(), payload.size());
  if (doc.HasParseError() || !doc.IsObject()) return no_safety_report(problem, "a response that is not a JSON object");
  const auto vud = doc.FindMember("vehicle_user_data");
  if (vud == doc.MemberEnd() || !vud->value.IsObject()) return no_safety_report(problem, "no vehicle_user_data");
  const auto user = vud->value.FindMember("user_data");
  if (user == vud->value.MemberEnd() || !user->value.IsObject())
    return no_safety_report(problem, "user_data is not an object");
  const rapidjson::Value& fields = user->value;
  SafetyReport report;
  report.time_us = time_us;
  const auto safe = fields.FindMember("safe_state");
  if (safe == fields.MemberEnd() || !safe->value.IsBool())
    return no_safety_report(problem, "user_data has no bool safe_state");
  report.safe_state = safe->value.GetBool();
  const auto drive = fields.FindMember("drive_state");
  const bool named = drive != fields.MemberEnd() && drive->value.IsString();
  const std::string state = named ? drive->value.GetString() : "";
  if (state != "enabled" && state != "disabled") {
    return no_safety_report(problem, "user_data has no drive_state \"enabled\" or \"disabled\"");
  }
  report.enabled = state == "enabled";
  if (!safety_number_field(fields, "throttle", report.throttle, problem) ||
      !safety_number_field(fields, "brake", report.brake, problem) ||
      !safety_number_field(fields, "steer", report.steer, problem)) {
    return std::nullopt;
  }
  return report;
}

std::string describe_report(const SafetyReport& r) {
  // + 0.0: a reported -0.0 prints as 0.000, not -0.000.
  return fmt::format("safe_state {}, drive_state {}, throttle {:.3f}, brake {:.3f}, steer {:.3f}", r.safe_state,
                     r.enabled ? "enabled" : "disabled", r.throttle + 0.0, r.brake + 0.0, r.steer + 0.0);
}

ScriptRun play_safety_script(CaseContext& context, std::uint64_t salt, const std::vector<SafetyPhase>& phases,
                             milliseconds silence) {
  std::size_t total = 0;
  for (const SafetyPhase& phase : phases) total += phase.frames;
  const CraftedRun crafted = send_crafted(context, total, milliseconds(10), silence, [&](std::size_t i) {
    CraftedControl control = phases[safety_phase_of(phases, i)].control;
    control.ack = crafted_pair(salt, i);
    return control;
  });
  const Observations observed = Observations::from(context.entries());
  ScriptRun run;
  run.end_us = context.now_us();
  run.last_frame_us = crafted.start_us;
  std::size_t first = 0;
  for (const SafetyPhase& phase : phases) {
    const std::int64_t sent =
        first < crafted.pairs.size() && phase.frames > 0 ? safety_sent_time(observed, crafted.pairs[first]) : -1;
    run.phase_start_us.push_back(sent >= 0 ? sent : run.end_us);
    first += phase.frames;
  }
  for (const AckPair& pair : crafted.pairs)
    run.last_frame_us = std::max(run.last_frame_us, safety_sent_time(observed, pair));
  collect_safety_reports(observed, run.phase_start_us.empty() ? crafted.start_us : run.phase_start_us.front(), run);
  return run;
}

void collect_safety_reports(const Observations& observed, std::int64_t from_us, ScriptRun& run) {
  for (const Response& response : observed.responses) {
    if (response.time_us < from_us || response.drained) continue;
    ++run.responses;
    std::string problem;
    if (auto report = read_safety_report(response.payload, response.time_us, problem)) {
      run.reports.push_back(*report);
    } else if (run.missing.empty()) {
      run.missing = problem;
    }
  }
}

std::optional<Outcome> safety_prologue(CaseContext& context) {
  const std::int64_t start = context.now_us();
  context.run_for(milliseconds(200));
  ScriptRun probe;
  collect_safety_reports(Observations::from(context.entries()), start, probe);
  if (probe.responses == 0) return std::nullopt;  // nothing to tell yet: the script decides
  return safety_not_judged(probe);
}

std::optional<Outcome> safety_not_judged(const ScriptRun& run) {
  if (!run.reports.empty()) return std::nullopt;
  const std::string why =
      run.responses == 0 ? std::string("no response during the script")
                         : fmt::format("none of {} responses carries a safety report ({})", run.responses, run.missing);
  return informational(
      "not judged: " + why +
      "; a client that reports safe_state, drive_state, throttle, brake and steer in vehicle_user_data.user_data "
      "is graded on SPEC §10 (docs/conformance.md, Safety report)");
}

Settling settle_within(const ScriptRun& run, std::int64_t from_us, std::int64_t to_us, std::int64_t bound_us,
                       const std::function<bool(const SafetyReport&)>& rule) {
  Settling settling;
  for (const SafetyReport& report : run.reports) {
    if (report.time_us < from_us || report.time_us >= to_us) continue;
    const bool keeps = rule(report);
    if (keeps && !settling.reached_after_us) settling.reached_after_us = report.time_us - from_us;
    if (report.time_us < from_us + bound_us) continue;
    ++settling.checked;
    if (!keeps && !settling.broken) settling.broken = report;
  }
  return settling;
}

std::string describe_settling(const Settling& settling, std::int64_t from_us, const std::string& what) {
  const std::string reached =
      settling.reached_after_us
          ? fmt::format("{} after {:.0f} ms", what, static_cast<double>(*settling.reached_after_us) / 1000.0)
          : fmt::format("never {}", what);
  if (settling.checked == 0) return reached + " (no report after the bound to check)";
  if (!settling.broken) return fmt::format("{}, kept in all {} reports after the bound", reached, settling.checked);
  return fmt::format("{}, but at +{:.0f} ms the report says {}", reached,
                     static_cast<double>(settling.broken->time_us - from_us) / 1000.0,
                     describe_report(*settling.broken));
}

std::optional<SafetyReport> last_report_before(const ScriptRun& run, std::int64_t time_us) {
  std::optional<SafetyReport> last;
  for (const SafetyReport& report : run.reports) {
    if (report.time_us < time_us) last = report;
  }
  return last;
}

CraftedControl pad_frame(const CraftedPad& pad, bool fault) {
  CraftedControl control;
  control.controller = CraftedController::pad;
  control.pad = pad;
  control.fault = fault;
  return control;
}

CraftedPad pad_pressing(const std::string& button, double right_trigger) {
  CraftedPad pad;
  pad.also_pressed = button;
  pad.right_trigger = right_trigger;
  return pad;
}

std::vector<SafetyPhase> enable_and_drive(std::size_t drive, const InterlockButtons& interlock) {
  return {{5, pad_frame(CraftedPad{})},
          {5, pad_frame(pad_pressing(interlock.enable))},
          {drive, pad_frame(CraftedPad{.right_trigger = 0.0})}};
}

}  // namespace ocp::conformance::detail
