// Scenario files: `expect.feedback`, what the operator client was sent in the Player's
// VehicleOcpShared about a vehicle (model.hpp FeedbackExpectation): a field's value and / or
// the whole sender and receiver fault lists, at an instant or through a window.
#include <algorithm>
#include <tuple>

#include "parser.hpp"

namespace ocp::scenario {
namespace {

// The members of a vehicle's entry (SPEC §4.1): the first step of every path.
const std::vector<std::string>& feedback_entry_fields() {
  static const std::vector<std::string> fields = {
      "ping_latency_ms", "message_latency_roundtrip", "ms_since_last_vehicle_data", "missing_cameras",
      "sender_fault",    "receiver_fault",            "vehicle_data",               "last_remote_input",
      "ack_time",        "ack_time_mac",              "is_monitor"};
  return fields;
}

}  // namespace

void Parser::feedback_expectation(const YAML::Node& node) {
  read_.check_keys(node, "feedback expectation",
                   {"vehicle", "field", "equals", "sender_fault", "receiver_fault", "at", "from", "until"});
  if (!scenario_.operator_client.connect) {
    read_.fail(node, "expect.feedback needs an operator client: world.operator_client: {connect: true}");
  }
  FeedbackExpectation e;
  e.vehicle = vehicle_of(node, "feedback expectation");
  if (node["field"] || node["equals"]) {
    const std::string field = feedback_field(read_.require(node, "field", "feedback expectation"));
    e.checks.push_back({field, read_.json(read_.require(node, "equals", "feedback expectation")), false});
  }
  for (const char* key : {"sender_fault", "receiver_fault"}) {
    if (node[key]) e.checks.push_back({key, fault_list(node[key], key), true});
  }
  if (e.checks.empty()) read_.fail(node, "a feedback expectation needs field + equals, sender_fault or receiver_fault");
  feedback_window(node, e);
  std::string title = "feedback on " + e.vehicle + ":";
  for (const FeedbackCheck& check : e.checks) title += " " + check.field + " = " + check.expected_json;
  title += e.instant ? " at " + e.from_label
                     : " from " + e.from_label + (e.until ? " until " + e.until_label : " to the end");
  scenario_.expectations.push_back({title, read_.mark(node), e});
}

// `at` (an instant) or `from` / `until` (a window; until defaults to the end of the run).
void Parser::feedback_window(const YAML::Node& node, FeedbackExpectation& e) {
  if (node["at"]) {
    if (node["from"] || node["until"]) read_.fail(node["at"], "at is an instant: no from / until beside it");
    e.instant = true;
    std::tie(e.from, e.from_label) = anchor(node["at"]);
    if (e.from > scenario_.duration) read_.fail(node["at"], "at is after the end of the run");
    e.until = e.from;
    e.until_label = e.from_label;
    return;
  }
  if (!node["from"]) read_.fail(node, "a feedback expectation needs at, or from (and until)");
  const ExpectWindow window = expect_window(node);
  if (window.from > scenario_.duration) read_.fail(node["from"], "from is after the end of the run");
  std::tie(e.from, e.from_label, e.until, e.until_label) = std::tie(window.from, window.from_label, window.until, window.until_label);
}

// A dotted path into the vehicle's entry: vehicle_data.user_data.mode, missing_cameras.0.
std::string Parser::feedback_field(const YAML::Node& node) {
  const std::string field = read_.text(node);
  if (field.empty() || field.front() == '.' || field.back() == '.' || field.find("..") != std::string::npos) {
    read_.fail(node, "field: expected a dotted path into the vehicle's feedback entry (vehicle_data.user_data.mode)");
  }
  const std::string first = field.substr(0, field.find('.'));
  const auto& fields = feedback_entry_fields();
  if (std::find(fields.begin(), fields.end(), first) == fields.end()) read_.fail_unknown(node, "feedback field", first, fields);
  return field;
}

// A list of fault identifiers of the list's side (SPEC §6: sender = operator, receiver =
// vehicle), as the JSON array it is compared with; [] for none.
std::string Parser::fault_list(const YAML::Node& node, std::string_view key) {
  if (!node.IsSequence()) read_.fail(node, std::string(key) + ": expected a list of fault identifiers ([] for none)");
  const FaultSide side = key == "sender_fault" ? FaultSide::operator_station : FaultSide::vehicle;
  std::vector<std::string> names;
  for (std::size_t i = 0; i < fault_count; ++i) {
    if (fault_side(static_cast<FaultId>(i)) == side) names.emplace_back(fault_identifier(static_cast<FaultId>(i)));
  }
  std::string json = "[";
  for (const auto& item : node) {
    const std::string name = read_.text(item);
    if (std::find(names.begin(), names.end(), name) == names.end()) {
      read_.fail_unknown(item, std::string(key) + " fault (" + (side == FaultSide::vehicle ? "a vehicle" : "an operator") + " fault)",
                         name, names);
    }
    json += (json.size() > 1 ? ",\"" : "\"") + name + "\"";
  }
  return json + "]";
}

}  // namespace ocp::scenario
