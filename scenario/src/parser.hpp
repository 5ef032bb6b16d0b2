#pragma once
// The scenario file parser's one class, internal to the parser: its methods live in
// parse.cpp (top level), parse_world.cpp, parse_timeline.cpp and parse_expect.cpp.
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "scenario/model.hpp"
#include "scenario/parse.hpp"
#include "sim_app/file_loaders.hpp"
#include "yaml_read.hpp"

namespace ocp::scenario {

// "12s", "350ms", "250us": how times appear in titles and errors.
std::string format_time(Micros time);

class Parser {
 public:
  explicit Parser(std::string path) : read_(path) { scenario_.path = std::move(path); }
  Scenario parse(const std::string& text);

 private:
  void world(const YAML::Node& node);
  void player(const YAML::Node& node);
  void operator_client(const YAML::Node& node);   // parse_operator.cpp
  VehicleSpec vehicle(const YAML::Node& node);
  // `targeted`: the timeline's misbehave action, which also names the vehicle.
  void misbehave(const YAML::Node& node, Misbehaviour& m, bool targeted = false);
  BadResponse bad_response(const YAML::Node& node);
  // `targeted`: the timeline's impair action, which also names vehicle and direction.
  ImpairmentPatch impairments(const YAML::Node& node, bool targeted = false);
  // A `trace:` value: the Mahimahi file, relative to the scenario file, loaded once per path.
  std::shared_ptr<const DeliveryTrace> delivery_trace(const YAML::Node& node);
  // A `replay:` value (parse_replay.cpp): the link recording, loaded once per path; `fields`
  // is the impairments node, whose other settings it must not be combined with.
  std::shared_ptr<const LinkRecording> link_recording(const YAML::Node& node, const YAML::Node& fields);
  // A file a link names (`trace:`, `replay:`): relative to the scenario file, loaded once per
  // path into `loaded`; a load error gives the file's own line, then where the scenario names it.
  template <class File>
  std::shared_ptr<const File> named_file(const YAML::Node& node, const std::string& key, const std::string& expected,
                                         std::map<std::string, std::shared_ptr<const File>>& loaded);
  // Each replayed direction of the vehicle has messages of its route in the recording.
  void check_replayed_routes(const VehicleSpec& spec, const YAML::Node& node);
  Controller controller(const YAML::Node& node);
  GamepadScriptSetting gamepad_script(const YAML::Node& node);
  const VehicleSpec* find_vehicle(const std::string& name) const;
  std::vector<std::string> vehicle_list() const;   // for "did you mean"
  // The `vehicle` key of an action; may be left out when the world has one vehicle.
  std::string vehicle_of(const YAML::Node& node, std::string_view what);
  Direction direction_of(const YAML::Node& node);
  void timeline(const YAML::Node& node);
  void action(const YAML::Node& item, TimelineEvent& event);
  void check_one_action(const YAML::Node& item);
  // The actions: each reads its node, names the event (`event.label`) and returns the action.
  SetImpairments impair_action(const YAML::Node& n, const YAML::Node& ramp, TimelineEvent& event);
  LinkOutage outage_action(const YAML::Node& n, TimelineEvent& event);
  CameraStall camera_stall_action(const YAML::Node& item, TimelineEvent& event);
  std::string camera_of(const YAML::Node& n, const VehicleSpec& spec);
  DisconnectVehicle disconnect_action(const YAML::Node& n, TimelineEvent& event);
  SetMisbehaviour misbehave_action(const YAML::Node& n, TimelineEvent& event);
  GamepadAction gamepad_action(const YAML::Node& n, TimelineEvent& event);
  SelectVehicle select_vehicle_action(const YAML::Node& n, TimelineEvent& event);
  ClientDataAction client_data(const YAML::Node& n, TimelineEvent& event);
  SetOperatorMisbehaviour operator_misbehave_action(const YAML::Node& n, TimelineEvent& event);   // parse_operator.cpp
  void warn_unknown_client_vehicle(const YAML::Node& node, const std::string& name, std::string_view effect);
  void expectations(const YAML::Node& node);
  // `after`: an event name or a time.
  std::pair<SimTime, std::string> anchor(const YAML::Node& node);
  void fault_expectation(const YAML::Node& node);
  // The three kinds of fault expectation, once fault_expectation has told which one a node is.
  void fault_never_expectation(const YAML::Node& node, FaultId fault, const std::optional<std::string>& vehicle);
  void fault_always_expectation(const YAML::Node& node, FaultId fault, std::optional<std::string> vehicle);
  struct ExpectWindow {
    SimTime from{0};
    std::string from_label;
    std::optional<SimTime> until;   // nullopt: the end of the run
    std::string until_label;
  };
  ExpectWindow expect_window(const YAML::Node& node);
  void fault_edge_expectations(const YAML::Node& node, FaultId fault, std::optional<std::string> vehicle);
  std::string edge_window(const YAML::Node& within, FaultEdgeExpectation& expectation);
  std::string within_window(const YAML::Node& within, Micros& min, Micros& max);
  void fault_state_expectation(const YAML::Node& node, FaultId fault);
  std::vector<std::string> vehicle_names(const YAML::Node& list, std::string_view key);
  void delivery_expectation(const YAML::Node& node);
  std::string delivery_what(const YAML::Node& node, DeliveryExpectation& e);
  std::vector<ControllerFieldValue> controller_field_values(const YAML::Node& node);
  // parse_expect_events.cpp: source locks and conflicts, connection closes and refusals.
  void event_expectation(const YAML::Node& node);
  ClientSource client_source(const YAML::Node& node);
  std::string event_subject(const YAML::Node& node, EventExpectation& e);
  // parse_expect_feedback.cpp: what the operator client was sent.
  void feedback_expectation(const YAML::Node& node);
  void feedback_window(const YAML::Node& node, FeedbackExpectation& e);
  std::string feedback_field(const YAML::Node& node);
  std::string fault_list(const YAML::Node& node, std::string_view key);
  void threshold_expectations(const YAML::Node& key, const YAML::Node& list);

  YamlReader read_;
  Scenario scenario_;
  // The file expects its world to refuse to start: the world checks that the simulator makes
  // too are left to it (parse_world.cpp).
  bool expects_refusal_ = false;
  std::map<std::string, std::shared_ptr<const DeliveryTrace>> delivery_traces_;
  std::map<std::string, std::shared_ptr<const LinkRecording>> link_recordings_;
};

template <class File>
std::shared_ptr<const File> Parser::named_file(const YAML::Node& node, const std::string& key, const std::string& expected,
                                               std::map<std::string, std::shared_ptr<const File>>& loaded) {
  const std::string name = read_.text(node);
  if (name.empty()) read_.fail(node, key + ": expected " + expected);
  std::filesystem::path path(name);
  if (path.is_relative()) path = std::filesystem::path(scenario_.path).parent_path() / path;
  const std::string file = path.lexically_normal().string();
  if (const auto known = loaded.find(file); known != loaded.end()) return known->second;
  // Read by the app layer's loaders (sim_app/file_loaders.hpp), parsed by the sans-IO parsers.
  auto opened = [&file] {
    if constexpr (std::is_same_v<File, DeliveryTrace>) {
      return sim_app::load_delivery_trace(file);
    } else {
      return sim_app::load_link_recording(file);
    }
  }();
  if (!opened) {
    const Mark at = read_.mark(node);
    throw ScenarioError(file, opened.error().detail + " (the " + key + " of " + read_.file() + ":" +
                                  std::to_string(at.line) + ":" + std::to_string(at.column) + ")");
  }
  auto shared = std::make_shared<const File>(std::move(opened).value());
  loaded.emplace(file, shared);
  return shared;
}

}  // namespace ocp::scenario
