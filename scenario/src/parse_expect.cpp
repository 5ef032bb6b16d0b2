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
  read_.check_keys(node, "expect", {"faults", "thresholds", "invariants", "delivered"});
  if (const YAML::Node delivered = node["delivered"]) {
    if (!delivered.IsSequence()) read_.fail(delivered, "expect.delivered: expected a list");
    for (const auto& item : delivered) delivery_expectation(item);
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
  read_.check_keys(node, "fault expectation", {"fault", "vehicle", "raised", "cleared", "never", "from", "at", "active_on", "inactive_on"});
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
  const bool state = static_cast<bool>(node["at"]);
  if (node["from"] && !never) read_.fail(node["from"], "from only applies to never");
  if (int(edges) + int(never) + int(state) != 1) {
    read_.fail(node, "a fault expectation needs one of: raised/cleared, never, at (with active_on / inactive_on)");
  }
  if (never) {
    fault_never_expectation(node, *fault, vehicle);
  } else if (edges) {
    fault_edge_expectations(node, *fault, vehicle);
  } else {
    fault_state_expectation(node, *fault);
  }
}

// `never: true`, from the start or `from` an anchor on.
void Parser::fault_never_expectation(const YAML::Node& node, FaultId fault, const std::optional<std::string>& vehicle) {
  if (!read_.boolean(node["never"])) read_.fail(node["never"], "never: only true makes sense");
  FaultNeverExpectation expectation{fault, vehicle, SimTime{0}};
  std::string title = std::string(fault_identifier(fault)) + " never raised" + (vehicle ? " on " + *vehicle : "");
  if (node["from"]) {
    std::string label;
    std::tie(expectation.from, label) = anchor(node["from"]);
    title += " from " + label;
  }
  scenario_.expectations.push_back({title, read_.mark(node), expectation});
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
  if (within.IsSequence()) {
    if (within.size() != 2) read_.fail(within, "within: expected [min, max] or one maximum");
    expectation.min = read_.duration(within[0]);
    expectation.max = read_.duration(within[1]);
    if (expectation.max < expectation.min) read_.fail(within, "within: max < min");
  } else {
    expectation.max = read_.duration(within);
  }
  if (expectation.min <= Micros{0}) return format_time(expectation.max);
  // Appended piece by piece: GCC 12 (-O3) reports a false -Wrestrict for "[" + a temporary.
  std::string text = "[";
  text += format_time(expectation.min);
  text += ", ";
  text += format_time(expectation.max);
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
  read_.check_keys(node, "delivered", {"vehicle", "after", "within", "controller", "user_data"});
  DeliveryExpectation e;
  e.vehicle = vehicle_of(node, "delivered");
  std::tie(e.after, e.after_label) = anchor(read_.require(node, "after", "delivered"));
  e.within = read_.duration(read_.require(node, "within", "delivered"));
  std::string what;
  if (const YAML::Node controller = node["controller"]) {
    const std::string state = controller.IsNull() ? "null" : read_.text(controller);
    if (state == "null") e.controller = DeliveryExpectation::ControllerState::null;
    else if (state == "default") e.controller = DeliveryExpectation::ControllerState::default_;
    else if (state == "driving") e.controller = DeliveryExpectation::ControllerState::driving;
    else if (state == "any") e.controller = DeliveryExpectation::ControllerState::any;
    else read_.fail_unknown(controller, "controller", state, {"null", "default", "driving", "any"});
    what += "controller " + state;
  }
  if (node["user_data"]) {
    e.user_data_json = read_.json(node["user_data"]);
    what += std::string(what.empty() ? "" : ", ") + "user_data " + *e.user_data_json;
  }
  if (what.empty()) read_.fail(node, "delivered: say what must arrive (controller and / or user_data)");
  if (find_vehicle(e.vehicle)->monitor) read_.fail(node, "a monitor vehicle is sent no control");
  scenario_.expectations.push_back(
      {e.vehicle + " received " + what + " within " + format_time(e.within) + " after " + e.after_label,
       read_.mark(node), e});
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
