// Delivery verdicts (verdicts_internal.hpp): what the control frames to a vehicle carried in a
// window — some frame (the default) or every frame (`every`) must match.
#include <cmath>

#include <rapidjson/document.h>

#include "player/gamepad.hpp"
#include "verdicts_internal.hpp"

namespace ocp::scenario {
bool same_json_value(const std::string& a, const std::string& b) {
  rapidjson::Document x, y;
  x.Parse(a.c_str());
  y.Parse(b.c_str());
  return !x.HasParseError() && !y.HasParseError() && x == y;
}

namespace {

std::string_view delivered_controller_name(Delivery::Controller controller) {
  switch (controller) {
    case Delivery::Controller::null: return "null";
    case Delivery::Controller::default_: return "default";
    case Delivery::Controller::driving: return "driving";
  }
  return "?";
}

std::string_view wanted_controller_name(DeliveryExpectation::ControllerState state) {
  using State = DeliveryExpectation::ControllerState;
  switch (state) {
    case State::any: return "any";
    case State::null: return "null";
    case State::default_: return "default";
    case State::driving: return "driving";
    case State::safe: return "safe (default or null)";
  }
  return "?";
}

bool controller_matches(DeliveryExpectation::ControllerState want, Delivery::Controller got) {
  using State = DeliveryExpectation::ControllerState;
  switch (want) {
    case State::any: return true;
    case State::null: return got == Delivery::Controller::null;
    case State::default_: return got == Delivery::Controller::default_;
    case State::driving: return got == Delivery::Controller::driving;
    case State::safe: return got != Delivery::Controller::driving;
  }
  return false;
}

// The wire carries axes as decimal text: equal within a rounding, not bit for bit.
bool fields_match(const std::vector<ControllerFieldValue>& fields, const std::optional<Controller>& controller) {
  if (fields.empty()) return true;
  if (!controller) return false;
  for (const ControllerFieldValue& field : fields) {
    const std::optional<double> value = controller_field(*controller, field.name);
    if (!value || std::abs(*value - field.value) > 1e-9) return false;
  }
  return true;
}

bool delivery_matches(const DeliveryExpectation& e, const Delivery& d) {
  if (!controller_matches(e.controller, d.controller) || !fields_match(e.fields, d.controller_value)) return false;
  if (e.user_data_absent) return !d.user_data_json.has_value();
  return !e.user_data_json || (d.user_data_json && same_json_value(*d.user_data_json, *e.user_data_json));
}

std::string field_text(const std::vector<ControllerFieldValue>& fields) {
  std::string text;
  for (const ControllerFieldValue& field : fields) text += (text.empty() ? "" : " ") + field.name + "=" + format_number(field.value);
  return text;
}

// What a frame carried, in the terms of the expectation.
std::string describe_delivery(const DeliveryExpectation& e, const Delivery& d) {
  std::string text = "controller " + std::string(delivered_controller_name(d.controller));
  if (!e.fields.empty() && d.controller_value) {
    std::vector<ControllerFieldValue> got;
    for (const ControllerFieldValue& field : e.fields) got.push_back({field.name, controller_field(*d.controller_value, field.name).value_or(0)});
    text += " (" + field_text(got) + ")";
  }
  return text + ", user_data " + d.user_data_json.value_or("none");
}

std::string expected_delivery(const DeliveryExpectation& e) {
  std::string text = e.every ? "every control frame with" : "a control frame with";
  // Appended piece by piece: GCC 12 (-O3) reports a false -Wrestrict for " " + a temporary.
  if (e.controller != DeliveryExpectation::ControllerState::any) text.append(" controller ").append(wanted_controller_name(e.controller));
  if (!e.fields.empty()) text.append(" ").append(field_text(e.fields));
  if (e.user_data_json) text.append(" user_data ").append(*e.user_data_json);
  if (e.user_data_absent) text += " no user_data";
  return text + " within " + verdict_ms_text(e.within) + " after " + e.after_label;
}

std::string truncated_note() {
  return " (only the first " + std::to_string(delivery_limit) + " control frames in delivery windows were kept)";
}

// `every`: all frames in the window match, and there was at least one.
void judge_every_delivery(const JudgeContext& context, const DeliveryExpectation& e, Verdict& v) {
  std::size_t checked = 0;
  for (const Delivery& d : context.observations.deliveries) {
    if (d.vehicle != e.vehicle || d.time < e.after || d.time > e.after + e.within) continue;
    ++checked;
    if (!delivery_matches(e, d)) {
      v.actual = "frame " + std::to_string(checked) + " in the window (at " + format_seconds(d.time) + ") did not: " +
                 describe_delivery(e, d);
      return;
    }
  }
  v.passed = checked > 0;
  v.actual = checked > 0 ? std::to_string(checked) + " control frames in the window, all did"
                         : "no control frame reached " + e.vehicle + " in the window: nothing checked";
  if (context.observations.deliveries_truncated) v.actual += truncated_note();
  if (!context.ran_past(e.after + e.within)) context.cut_short(v);
}

}  // namespace

void judge_delivery(const JudgeContext& context, const DeliveryExpectation& e, Verdict& v) {
  v.kind = "delivery";
  v.expected = expected_delivery(e);
  if (e.every) return judge_every_delivery(context, e, v);
  const Delivery* last = nullptr;
  for (const Delivery& d : context.observations.deliveries) {
    if (d.vehicle != e.vehicle || d.time < e.after || d.time > e.after + e.within) continue;
    if (delivery_matches(e, d)) {
      v.passed = true;
      v.actual = "received " + verdict_ms_text(d.time - e.after) + " after " + e.after_label + " (at " + format_seconds(d.time) + ")";
      return;
    }
    last = &d;
  }
  v.actual = last == nullptr ? "no control frame reached " + e.vehicle + " in the window"
                             : "last frame in the window: " + describe_delivery(e, *last);
  if (context.observations.deliveries_truncated) v.actual += truncated_note();
  if (!context.ran_past(e.after + e.within)) context.cut_short(v);
}

}  // namespace ocp::scenario
