// Scenario files: the operator side's stand-in client (world.operator_client) and its
// misbehaviours on the Player's :4001 port (the timeline's operator_misbehave).
#include <algorithm>

#include "parser.hpp"

namespace ocp::scenario {
namespace {

// Long enough for any scenario, short enough that a typo in the unit (1000s) is caught.
constexpr Micros operator_client_max_period{60'000'000};

}  // namespace

void Parser::operator_client(const YAML::Node& node) {
  read_.check_keys(node, "world.operator_client", {"connect", "keep_alive_period", "reconnect_backoff"});
  OperatorClientSetting& setting = scenario_.operator_client;
  if (node["connect"]) setting.connect = read_.boolean(node["connect"]);
  for (const char* key : {"keep_alive_period", "reconnect_backoff"}) {
    if (!node[key]) continue;
    const Micros value = read_.duration(node[key]);
    if (value <= Micros{0} || value > operator_client_max_period) {
      read_.fail(node[key], std::string(key) + " must be > 0 and <= " + format_time(operator_client_max_period));
    }
    (std::string_view(key) == "keep_alive_period" ? setting.keep_alive_period : setting.reconnect_backoff) = value;
  }
}

// `operator_misbehave: {silent: true}`: replaces the client's misbehaviours (all off = well-behaved).
SetOperatorMisbehaviour Parser::operator_misbehave_action(const YAML::Node& n, TimelineEvent& event) {
  read_.check_keys(n, "operator_misbehave", {"silent", "malformed_json", "oversized_frames", "bad_message", "second_connection"});
  if (!scenario_.operator_client.connect) {
    read_.fail(n, "operator_misbehave needs an operator client: world.operator_client: {connect: true}");
  }
  SetOperatorMisbehaviour set;
  OperatorMisbehaviour& m = set.misbehave;
  if (n["silent"]) m.silent = read_.boolean(n["silent"]);
  if (n["malformed_json"]) m.malformed_json = read_.boolean(n["malformed_json"]);
  if (n["oversized_frames"]) m.oversized_frames = read_.boolean(n["oversized_frames"]);
  if (const YAML::Node bad = n["bad_message"]) {
    const std::string name = read_.text(bad);
    std::vector<std::string> names;
    for (auto kind : {BadClientMessage::none, BadClientMessage::not_an_object, BadClientMessage::wrong_type,
                      BadClientMessage::eof_mid_frame}) {
      names.emplace_back(bad_client_message_name(kind));
      if (names.back() == name) m.bad_message = kind;
    }
    if (std::find(names.begin(), names.end(), name) == names.end()) read_.fail_unknown(bad, "bad_message", name, names);
  }
  if (n["second_connection"]) set.second_connection = read_.boolean(n["second_connection"]);
  event.label = std::string("operator misbehave") + (m.any() ? "" : " (all off)") +
                (set.second_connection ? ", second connection" : "");
  return set;
}

}  // namespace ocp::scenario
