// Feedback verdicts (verdicts_internal.hpp): what the operator client was sent in the Player's
// VehicleOcpShared about a vehicle — a field's value or a whole fault list — at an instant or
// through a window. The value counted at an instant is the one of the last frame sent by then.
#include <rapidjson/document.h>

#include <set>

#include "verdicts_internal.hpp"

namespace ocp::scenario {
namespace {

// A JSON array of strings as a set; nullopt when it is not one (null counts as empty).
std::optional<std::set<std::string>> feedback_name_set(const std::string& json) {
  rapidjson::Document document;
  document.Parse(json.c_str());
  if (document.HasParseError()) return std::nullopt;
  std::set<std::string> names;
  if (document.IsNull()) return names;
  if (!document.IsArray()) return std::nullopt;
  for (const auto& item : document.GetArray()) {
    if (!item.IsString()) return std::nullopt;
    names.emplace(item.GetString(), item.GetStringLength());
  }
  return names;
}

bool feedback_value_matches(const FeedbackCheck& check, const std::string& actual) {
  if (actual.empty()) return false;   // absent
  if (!check.as_set) return same_json_value(check.expected_json, actual);
  const auto want = feedback_name_set(check.expected_json);
  const auto got = feedback_name_set(actual);
  return want && got && *want == *got;
}

std::string feedback_value_text(const std::string& json) { return json.empty() ? "absent" : json; }

struct FeedbackOutcome {
  bool passed = false;
  std::string actual;
};

// The check over [from, until]: the value in effect at `from`, then every change up to `until`.
FeedbackOutcome judge_feedback_check(const FeedbackSeries* series, const FeedbackCheck& check, SimTime from, SimTime until) {
  const std::string name = check.field;
  if (series == nullptr || series->changes.empty()) return {false, "no VehicleOcpShared was sent to the operator client"};
  const std::vector<FeedbackValue>& changes = series->changes;
  if (changes.front().time > from) {
    return {false, "no VehicleOcpShared sent to the operator client by " + format_seconds(from) + " (the first at " +
                       format_seconds(changes.front().time) + ")"};
  }
  std::size_t at = 0;
  while (at + 1 < changes.size() && changes[at + 1].time <= from) ++at;
  for (std::size_t i = at; i < changes.size() && (i == at || changes[i].time <= until); ++i) {
    if (!feedback_value_matches(check, changes[i].json)) {
      const SimTime when = std::max(from, changes[i].time);
      return {false, name + " = " + feedback_value_text(changes[i].json) + " at " + format_seconds(when)};
    }
  }
  if (series->truncated && changes.back().time < until) {
    return {false, name + " changed more than " + std::to_string(feedback_change_limit) + " times: not followed after " +
                       format_seconds(changes.back().time)};
  }
  return {true, name + " = " + changes[at].json + (from == until ? "" : " throughout")};
}

std::string feedback_expected_text(const FeedbackExpectation& e, SimTime until) {
  std::string text;
  for (const FeedbackCheck& check : e.checks) {
    text += (text.empty() ? "" : ", ") + check.field + " = " + check.expected_json + (check.as_set ? " (as a set)" : "");
  }
  text += " on " + e.vehicle;
  if (e.instant) return text + " at " + format_seconds(e.from);
  return text + " from " + format_seconds(e.from) + " until " + format_seconds(until);
}

}  // namespace

void judge_feedback(const JudgeContext& context, const FeedbackExpectation& e, Verdict& v) {
  v.kind = "feedback";
  const SimTime until = e.instant ? e.from : e.until.value_or(context.scenario.duration);
  v.expected = feedback_expected_text(e, until);
  std::string actual;
  for (const FeedbackCheck& check : e.checks) {
    const auto found = context.observations.feedback.find(feedback_key(e.vehicle, check.field));
    const FeedbackSeries* series = found == context.observations.feedback.end() ? nullptr : &found->second;
    FeedbackOutcome outcome = judge_feedback_check(series, check, e.from, until);
    if (!outcome.passed) {
      v.actual = std::move(outcome.actual);
      if (!context.ran_past(until)) context.cut_short(v);
      return;
    }
    actual += (actual.empty() ? "" : ", ") + outcome.actual;
  }
  v.passed = true;
  v.actual = std::move(actual);
  if (!context.ran_past(until)) context.cut_short(v);
}

}  // namespace ocp::scenario
