// Scenario files: the `expect` section (fault edges, never, states, thresholds, deliveries,
// invariants); every expectation must name something that exists.
#include <algorithm>
#include <set>
#include <sstream>
#include <tuple>

#include "did_you_mean.hpp"
#include "parser.hpp"

namespace ocp::scenario {

void Parser::expectations(const YAML::Node& node) {
  read_.check_keys(node, "expect", {"faults", "thresholds", "invariants", "delivered", "refuses_to_start", "events",
                                        "feedback"});
  if (const YAML::Node refusal = node["refuses_to_start"]) {
    // A world that never starts has nothing else to judge.
    if (node.size() != 1) read_.fail(refusal, "refuses_to_start is the only expectation a world that never starts can have");
    const std::string reason = refusal.IsNull() ? "" : read_.text(refusal);
    scenario_.expectations.push_back({"the world refuses to start: \"" + reason + "\"", read_.mark(refusal),
                                      RefusesToStartExpectation{reason}});
    return;
  }
  if (const YAML::Node delivered = node["delivered"]) {
    if (!delivered.IsSequence()) read_.fail(delivered, "expect.delivered: expected a list");
    for (const auto& item : delivered) delivery_expectation(item);
  }
  if (const YAML::Node events = node["events"]) {
    if (!events.IsSequence()) read_.fail(events, "expect.events: expected a list");
    for (const auto& item : events) event_expectation(item);
  }
  if (const YAML::Node feedback = node["feedback"]) {
    if (!feedback.IsSequence()) read_.fail(feedback, "expect.feedback: expected a list");
    for (const auto& item : feedback) feedback_expectation(item);
  }
  if (const YAML::Node faults = node["faults"]) {
    if (!faults.IsSequence()) read_.fail(faults, "expect.faults: expected a list");
    for (const auto& item : faults) fault_expectation(item);
  }
  if (const YAML::Node thresholds = node["thresholds"]) {
    if (!thresholds.IsMap()) read_.fail(thresholds, "expect.thresholds: expected a mapping metric → list");
    for (const auto& item : thresholds) threshold_expectations(item.first, item.second);
  }
  if (const YAML::Node invariants = node["invariants"]) {
    if (!invariants.IsSequence()) read_.fail(invariants, "expect.invariants: expected a list");
    for (const auto& item : invariants) {
      const std::string name = read_.text(item);
      InvariantExpectation expectation;
      if (name == invariant_name(Invariant::default_controller_during_control_fault)) {
        expectation.invariant = Invariant::default_controller_during_control_fault;
      } else if (name == invariant_name(Invariant::no_stale_pair_after_reconnect)) {
        expectation.invariant = Invariant::no_stale_pair_after_reconnect;
      } else {
        read_.fail_unknown(item, "invariant", name,
                           {std::string(invariant_name(Invariant::default_controller_during_control_fault)),
                            std::string(invariant_name(Invariant::no_stale_pair_after_reconnect))});
      }
      scenario_.expectations.push_back({"invariant " + name, read_.mark(item), expectation});
    }
  }
  if (scenario_.expectations.empty()) read_.fail(node, "expect: no expectation (a scenario must check something)");
}

// `after`: an event name or a time.
std::pair<SimTime, std::string> Parser::anchor(const YAML::Node& node) {
  const std::string text = read_.text(node);
  std::vector<std::string> names;
  for (const TimelineEvent& event : scenario_.timeline) {
    if (!event.name.empty() && event.name == text) return {event.at, text};
    if (!event.name.empty()) names.push_back(event.name);
  }
  try {
    return {parse_duration_text(text), text};
  } catch (const std::invalid_argument&) {
    std::string reason = "'" + text + "' names no timeline event (and is not a time)";
    if (const auto close = closest_name(text, names)) reason += ": did you mean '" + *close + "'?";
    read_.fail(node, reason);
  }
}

void Parser::fault_expectation(const YAML::Node& node) {
  read_.check_keys(node, "fault expectation", {"fault", "vehicle", "raised", "cleared", "never", "always", "from", "until",
                                               "at", "active_on", "inactive_on"});
  const YAML::Node fault_node = read_.require(node, "fault", "fault expectation");
  const auto fault = parse_fault_identifier(read_.text(fault_node));
  if (!fault) {
    std::vector<std::string> faults;
    for (std::size_t i = 0; i < fault_count; ++i) faults.emplace_back(fault_identifier(static_cast<FaultId>(i)));
    read_.fail_unknown(fault_node, "fault", fault_node.Scalar(), faults);
  }
  std::optional<std::string> vehicle;
  if (node["vehicle"]) vehicle = vehicle_of(node, "fault expectation");
  const bool edges = node["raised"] || node["cleared"];
  const bool never = static_cast<bool>(node["never"]);
  const bool always = static_cast<bool>(node["always"]);
  const bool state = static_cast<bool>(node["at"]);
  for (const char* key : {"from", "until"}) {
    if (node[key] && !never && !always) read_.fail(node[key], std::string(key) + " only applies to never and always");
  }
  if (int(edges) + int(never) + int(always) + int(state) != 1) {
    read_.fail(node, "a fault expectation needs one of: raised/cleared, never, always, at (with active_on / inactive_on)");
  }
  if (never) {
    fault_never_expectation(node, *fault, vehicle);
  } else if (always) {
    fault_always_expectation(node, *fault, vehicle);
  } else if (edges) {
    fault_edge_expectations(node, *fault, vehicle);
  } else {
    fault_state_expectation(node, *fault);
  }
}

// `never: true`, from the start or `from` an anchor on, to the end or `until` an anchor.
void Parser::fault_never_expectation(const YAML::Node& node, FaultId fault, const std::optional<std::string>& vehicle) {
  if (!read_.boolean(node["never"])) read_.fail(node["never"], "never: only true makes sense");
  FaultNeverExpectation expectation{fault, vehicle, SimTime{0}, std::nullopt};
  std::string title = std::string(fault_identifier(fault)) + " never raised" + (vehicle ? " on " + *vehicle : "");
  const ExpectWindow window = expect_window(node);
  expectation.from = window.from;
  expectation.until = window.until;
  if (node["from"]) title += " from " + window.from_label;
  if (window.until) title += " until " + window.until_label;
  scenario_.expectations.push_back({title, read_.mark(node), expectation});
}

// `always: true`: active through the whole window, on one vehicle.
void Parser::fault_always_expectation(const YAML::Node& node, FaultId fault, std::optional<std::string> vehicle) {
  if (!read_.boolean(node["always"])) read_.fail(node["always"], "always: only true makes sense");
  if (!node["from"]) read_.fail(node, "always needs from (when the fault must be active already)");
  if (!vehicle) {
    if (scenario_.world.vehicles.size() != 1) read_.fail(node, "name the vehicle (the world has several)");
    vehicle = scenario_.world.vehicles.front().name;
  }
  const ExpectWindow window = expect_window(node);
  FaultAlwaysExpectation e{fault, *vehicle, window.from, window.from_label, window.until, window.until_label};
  scenario_.expectations.push_back({std::string(fault_identifier(fault)) + " active on " + *vehicle + " from " +
                                        window.from_label + " until " + (window.until ? window.until_label : "the end"),
                                    read_.mark(node), e});
}

// `from` (default: the start) and `until` (default or `end`: the end of the run), each an
// event name or a time, in order.
Parser::ExpectWindow Parser::expect_window(const YAML::Node& node) {
  ExpectWindow window;
  window.from_label = "0s";
  if (node["from"]) std::tie(window.from, window.from_label) = anchor(node["from"]);
  if (const YAML::Node until = node["until"]; until && !(until.IsScalar() && until.Scalar() == "end")) {
    SimTime time{0};
    std::tie(time, window.until_label) = anchor(until);
    if (time <= window.from) read_.fail(until, "until must be after from");
    if (time > scenario_.duration) read_.fail(until, "until is after the end of the run");
    window.until = time;
  }
  return window;
}

// `raised` and/or `cleared`: one expectation each, on one vehicle (an edge happens somewhere).
void Parser::fault_edge_expectations(const YAML::Node& node, FaultId fault, std::optional<std::string> vehicle) {
  if (!vehicle) {
    if (scenario_.world.vehicles.size() != 1) read_.fail(node, "name the vehicle (the world has several)");
    vehicle = scenario_.world.vehicles.front().name;
  }
  for (const char* key : {"raised", "cleared"}) {
    const YAML::Node edge = node[key];
    if (!edge) continue;
    read_.check_keys(edge, key, {"after", "within"});
    FaultEdgeExpectation expectation;
    expectation.fault = fault;
    expectation.vehicle = *vehicle;
    expectation.raised = std::string(key) == "raised";
    std::tie(expectation.after, expectation.after_label) = anchor(read_.require(edge, "after", key));
    const std::string window = edge_window(read_.require(edge, "within", key), expectation);
    scenario_.expectations.push_back(
        {std::string(fault_identifier(fault)) + " " + key + " within " + window + " after " + expectation.after_label +
             " on " + *vehicle,
         read_.mark(edge), expectation});
  }
}

// `within`: [min, max], or just a maximum; returns the window as the title shows it.
std::string Parser::edge_window(const YAML::Node& within, FaultEdgeExpectation& expectation) {
  return within_window(within, expectation.min, expectation.max);
}

// The same `within` for any expectation with an anchor (faults, events).
std::string Parser::within_window(const YAML::Node& within, Micros& min, Micros& max) {
  if (within.IsSequence()) {
    if (within.size() != 2) read_.fail(within, "within: expected [min, max] or one maximum");
    min = read_.duration(within[0]);
    max = read_.duration(within[1]);
    if (max < min) read_.fail(within, "within: max < min");
  } else {
    max = read_.duration(within);
  }
  if (min <= Micros{0}) return format_time(max);
  // Appended piece by piece: GCC 12 (-O3) reports a false -Wrestrict for "[" + a temporary.
  std::string text = "[";
  text += format_time(min);
  text += ", ";
  text += format_time(max);
  text += "]";
  return text;
}

// `at` a time: active on some vehicles, inactive on others.
void Parser::fault_state_expectation(const YAML::Node& node, FaultId fault) {
  FaultStateExpectation expectation;
  expectation.fault = fault;
  expectation.at = read_.duration(node["at"]);
  if (expectation.at > scenario_.duration) read_.fail(node["at"], "at is after the end of the run");
  if (const YAML::Node list = node["active_on"]) {
    // Which vehicle is active can change during a run: this one the file cannot list by name.
    if (list.IsScalar() && list.Scalar() == "every_vehicle_but_active") {
      expectation.every_vehicle_but_active = true;
    } else {
      expectation.active_on = vehicle_names(list, "active_on");
    }
  }
  if (const YAML::Node list = node["inactive_on"]) expectation.inactive_on = vehicle_names(list, "inactive_on");
  if (!expectation.every_vehicle_but_active && expectation.active_on.empty() && expectation.inactive_on.empty()) {
    read_.fail(node, "at: say on which vehicles (active_on: [...], inactive_on: [...] or active_on: every_vehicle_but_active)");
  }
  std::string title = std::string(fault_identifier(fault)) + " at " + format_time(expectation.at) + ": ";
  if (expectation.every_vehicle_but_active) title += "active on every vehicle but the active one";
  else {
    for (const auto& name : expectation.active_on) title += "active on " + name + " ";
    for (const auto& name : expectation.inactive_on) title += "inactive on " + name + " ";
    title.pop_back();
  }
  scenario_.expectations.push_back({title, read_.mark(node), expectation});
}

// A list of vehicles, each of which must exist.
std::vector<std::string> Parser::vehicle_names(const YAML::Node& list, std::string_view key) {
  if (!list.IsSequence()) read_.fail(list, std::string(key) + ": expected a list of vehicles");
  std::vector<std::string> names;
  for (const auto& item : list) {
    const std::string name = read_.text(item);
    if (find_vehicle(name) == nullptr) read_.fail_unknown(item, "vehicle", name, vehicle_list());
    names.push_back(name);
  }
  return names;
}

void Parser::delivery_expectation(const YAML::Node& node) {
  read_.check_keys(node, "delivered", {"vehicle", "after", "within", "every", "controller", "fields", "user_data", "no_user_data"});
  DeliveryExpectation e;
  e.vehicle = vehicle_of(node, "delivered");
  std::tie(e.after, e.after_label) = anchor(read_.require(node, "after", "delivered"));
  e.within = read_.duration(read_.require(node, "within", "delivered"));
  if (node["every"]) e.every = read_.boolean(node["every"]);
  std::string what = delivery_what(node, e);
  if (what.empty()) read_.fail(node, "delivered: say what must arrive (controller, fields, user_data and / or no_user_data)");
  if (find_vehicle(e.vehicle)->monitor) read_.fail(node, "a monitor vehicle is sent no control");
  const std::string title = e.every ? "every control frame to " + e.vehicle + " within " + format_time(e.within) +
                                          " after " + e.after_label + ": " + what
                                    : e.vehicle + " received " + what + " within " + format_time(e.within) + " after " +
                                          e.after_label;
  scenario_.expectations.push_back({title, read_.mark(node), e});
}

// What a delivered frame must carry; returns it as the title shows it ("" for nothing).
std::string Parser::delivery_what(const YAML::Node& node, DeliveryExpectation& e) {
  using State = DeliveryExpectation::ControllerState;
  std::string what;
  auto add = [&](const std::string& part) { what += (what.empty() ? "" : ", ") + part; };
  if (const YAML::Node controller = node["controller"]) {
    const std::string state = controller.IsNull() ? "null" : read_.text(controller);
    static const std::vector<std::pair<std::string, State>> states = {
        {"null", State::null}, {"default", State::default_}, {"driving", State::driving}, {"safe", State::safe}, {"any", State::any}};
    const auto found = std::find_if(states.begin(), states.end(), [&](const auto& s) { return s.first == state; });
    if (found == states.end()) read_.fail_unknown(controller, "controller", state, {"null", "default", "driving", "safe", "any"});
    e.controller = found->second;
    add("controller " + state);
  }
  if (const YAML::Node fields = node["fields"]) {
    e.fields = controller_field_values(fields);
    if (e.controller == State::null) read_.fail(fields, "fields: a null controller has no fields");
    add(read_.text(fields));
  }
  if (node["user_data"] && node["no_user_data"]) read_.fail(node["no_user_data"], "user_data and no_user_data exclude each other");
  if (node["user_data"]) {
    e.user_data_json = read_.json(node["user_data"]);
    add("user_data " + *e.user_data_json);
  }
  if (node["no_user_data"]) {
    if (!read_.boolean(node["no_user_data"])) read_.fail(node["no_user_data"], "no_user_data: only true makes sense");
    e.user_data_absent = true;
    add("no user_data");
  }
  return what;
}

// "right_trigger=0.4 a=1": the recording format's fields (player/gamepad.hpp), each checked.
std::vector<ControllerFieldValue> Parser::controller_field_values(const YAML::Node& node) {
  std::vector<ControllerFieldValue> values;
  std::istringstream in(read_.text(node));
  for (std::string field; in >> field;) {
    // The recording parser knows each name's range: a one-field state it accepts is valid.
    auto parsed = parse_recording("0 " + field);
    if (!parsed) read_.fail(node, "bad field '" + field + "': " + parsed.error().detail);
    const auto equals = field.find('=');
    ControllerFieldValue value{field.substr(0, equals), 0.0};
    value.value = controller_field(parsed->states.front().controller, value.name).value_or(0.0);
    values.push_back(value);
  }
  if (values.empty()) read_.fail(node, "fields: expected name=value pairs like \"right_trigger=0.4 a=1\"");
  return values;
}

void Parser::threshold_expectations(const YAML::Node& key, const YAML::Node& list) {
  static const std::vector<std::string> metrics = {"latency_ms", "echo_delay_ms", "control_gap_ms",
                                                   "feedback_gap_ms", "lost_to_streamer", "lost_to_player"};
  std::string metric = read_.text(key);
  std::optional<std::string> vehicle;
  if (const auto brace = metric.find('{'); brace != std::string::npos) {
    if (metric.back() != '}') read_.fail(key, "metric{vehicle}: missing '}'");
    vehicle = metric.substr(brace + 1, metric.size() - brace - 2);
    metric = metric.substr(0, brace);
    if (find_vehicle(*vehicle) == nullptr) read_.fail_unknown(key, "vehicle", *vehicle, vehicle_list());
  }
  if (std::find(metrics.begin(), metrics.end(), metric) == metrics.end()) read_.fail_unknown(key, "metric", metric, metrics);
  if (!list.IsSequence() || list.size() == 0) read_.fail(list, "thresholds: expected a non-empty list like [\"p(99) < 150\"]");
  for (const auto& item : list) {
    ThresholdExpectation t;
    t.metric = metric;
    t.vehicle = vehicle;
    t.text = read_.text(item);
    std::istringstream in(t.text);
    std::string number_text;
    in >> t.aggregate >> t.op >> number_text;
    std::string rest;
    if (!in || (in >> rest)) read_.fail(item, "threshold '" + t.text + "': expected '<aggregate> <op> <number>'");
    if (t.aggregate.rfind("p(", 0) == 0 && t.aggregate.back() == ')') {
      char* end = nullptr;
      const std::string inner = t.aggregate.substr(2, t.aggregate.size() - 3);
      t.percentile = std::strtod(inner.c_str(), &end);
      if (inner.empty() || *end != '\0' || t.percentile < 0 || t.percentile > 100) read_.fail(item, "bad percentile in '" + t.text + "'");
    } else if (!std::set<std::string>{"avg", "min", "max", "med", "count", "rate"}.count(t.aggregate)) {
      read_.fail_unknown(item, "aggregate", t.aggregate, {"avg", "min", "max", "med", "count", "rate", "p(99)"});
    }
    if (!std::set<std::string>{"<", "<=", ">", ">=", "==", "!="}.count(t.op)) read_.fail(item, "unknown operator '" + t.op + "'");
    const bool counter = metric.rfind("lost_", 0) == 0;
    if (counter && t.aggregate != "count" && t.aggregate != "rate") {
      read_.fail(item, metric + " counts messages: use count or rate, not " + t.aggregate);
    }
    if (!counter && t.aggregate == "rate") read_.fail(item, "rate applies to lost_to_streamer / lost_to_player only");
    char* end = nullptr;
    t.value = std::strtod(number_text.c_str(), &end);
    if (*end != '\0') read_.fail(item, "bad number '" + number_text + "' in '" + t.text + "'");
    scenario_.expectations.push_back({read_.text(key) + ": " + t.text, read_.mark(item), t});
  }
}

}  // namespace ocp::scenario
