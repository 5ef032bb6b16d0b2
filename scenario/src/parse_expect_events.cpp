// Scenario files: `expect.events`, the notable events of a run (model.hpp EventExpectation):
// client-data source locks and conflicts, connection closes (with a reason) and refusals.
#include <algorithm>
#include <tuple>

#include "parser.hpp"

namespace ocp::scenario {

void Parser::event_expectation(const YAML::Node& node) {
  read_.check_keys(node, "event expectation", {"event", "vehicle", "wire", "source", "locked", "reason", "after", "within",
                                               "never", "from", "until"});
  EventExpectation e;
  const YAML::Node kind = read_.require(node, "event", "event expectation");
  const std::string name = read_.text(kind);
  const std::vector<std::string> kinds = {"source_locked", "source_conflict", "connection_closed", "connection_refused"};
  const auto found = std::find(kinds.begin(), kinds.end(), name);
  if (found == kinds.end()) read_.fail_unknown(kind, "event", name, kinds);
  e.kind = static_cast<NotableKind>(found - kinds.begin());
  const std::string subject = event_subject(node, e);
  e.never = node["never"] && read_.boolean(node["never"]);
  if (node["never"] && !e.never) read_.fail(node["never"], "never: only true makes sense");
  std::string title = name + subject;
  if (e.never) {
    if (node["after"] || node["within"]) read_.fail(node, "never takes from / until, not after / within");
    const ExpectWindow window = expect_window(node);
    std::tie(e.from, e.from_label, e.until) = std::tie(window.from, window.from_label, window.until);
    title += " never";
    if (node["from"]) title += " from " + window.from_label;
    if (window.until) title += " until " + window.until_label;
  } else {
    if (node["from"] || node["until"]) read_.fail(node, "from / until go with never; an event that must happen takes after / within");
    std::tie(e.from, e.from_label) = anchor(read_.require(node, "after", "event expectation"));
    Micros max{0};
    const std::string window = within_window(read_.require(node, "within", "event expectation"), e.min, max);
    e.until = e.from + max;
    title += " within " + window + " after " + e.from_label;
  }
  scenario_.expectations.push_back({title, read_.mark(node), e});
}

// Which event: the source(s) of a lock or conflict, the wire, vehicle and reason of a
// connection event. Returns it as the title shows it (" plugin", " on truck-1 'reset'").
std::string Parser::event_subject(const YAML::Node& node, EventExpectation& e) {
  const bool source_event = e.kind == NotableKind::source_locked || e.kind == NotableKind::source_conflict;
  for (const char* key : {"vehicle", "wire", "reason"}) {
    if (node[key] && source_event) read_.fail(node[key], std::string(key) + " applies to connection events only");
  }
  for (const char* key : {"source", "locked"}) {
    if (node[key] && !source_event) read_.fail(node[key], std::string(key) + " applies to source_locked / source_conflict only");
  }
  if (node["locked"] && e.kind != NotableKind::source_conflict) read_.fail(node["locked"], "locked applies to source_conflict only");
  std::string subject;
  if (node["locked"]) {
    e.locked = client_source(node["locked"]);
    subject += " locked " + std::string(client_source_name(*e.locked));
  }
  if (node["source"]) {
    e.source = client_source(node["source"]);
    subject += (e.kind == NotableKind::source_conflict ? " offending " : " ") + std::string(client_source_name(*e.source));
  }
  if (node["wire"]) {
    const std::string wire = read_.text(node["wire"]);
    if (wire == "operator") e.wire = Wire::operator_;
    else if (wire != "vehicle") read_.fail_unknown(node["wire"], "wire", wire, {"vehicle", "operator"});
    subject += " on the " + wire + " wire";
  }
  if (node["vehicle"]) {
    if (e.wire == Wire::operator_) read_.fail(node["vehicle"], "the operator wire is the Player's: no vehicle");
    e.vehicle = vehicle_of(node, "event expectation");
    subject += " on " + *e.vehicle;
  }
  if (node["reason"]) {
    e.reason = read_.text(node["reason"]);
    subject += " '" + e.reason + "'";
  }
  return subject;
}

ClientSource Parser::client_source(const YAML::Node& node) {
  const std::string name = read_.text(node);
  for (ClientSource source : {ClientSource::tcp, ClientSource::webview, ClientSource::plugin}) {
    if (client_source_name(source) == name) return source;
  }
  read_.fail_unknown(node, "source", name, {"tcp", "webview", "plugin"});
}

}  // namespace ocp::scenario
