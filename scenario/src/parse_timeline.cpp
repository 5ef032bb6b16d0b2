// Scenario files: the `timeline` section (events in time order, one action each).
#include <algorithm>
#include <set>

#include "did_you_mean.hpp"

#include "parser.hpp"

namespace ocp::scenario {

std::vector<std::string> Parser::vehicle_list() const {
  std::vector<std::string> names;
  for (const VehicleSpec& spec : scenario_.world.vehicles) names.push_back(spec.name);
  return names;
}

const VehicleSpec* Parser::find_vehicle(const std::string& name) const {
  for (const VehicleSpec& spec : scenario_.world.vehicles) {
    if (spec.name == name) return &spec;
  }
  return nullptr;
}

// The `vehicle` key of an action; may be left out when the world has one vehicle.
std::string Parser::vehicle_of(const YAML::Node& node, std::string_view what) {
  if (!node["vehicle"]) {
    if (scenario_.world.vehicles.size() == 1) return scenario_.world.vehicles.front().name;
    read_.fail(node, std::string(what) + ": name the vehicle (the world has several)");
  }
  const std::string name = read_.text(node["vehicle"]);
  if (find_vehicle(name) == nullptr) read_.fail_unknown(node["vehicle"], "vehicle", name, vehicle_list());
  return name;
}

Direction Parser::direction_of(const YAML::Node& node) {
  if (!node["direction"]) return Direction::both;
  const std::string name = read_.text(node["direction"]);
  if (name == "both") return Direction::both;
  if (name == "to_streamer") return Direction::to_streamer;
  if (name == "to_player") return Direction::to_player;
  read_.fail_unknown(node["direction"], "direction", name, {"both", "to_streamer", "to_player"});
}

void Parser::timeline(const YAML::Node& node) {
  if (!node.IsSequence()) read_.fail(node, "timeline: expected a list of events");
  SimTime previous{0};
  std::set<std::string> names;
  for (const auto& item : node) {
    read_.check_keys(item, "timeline event",
                     {"at", "name", "impair", "ramp", "outage", "camera_stall", "camera_unstall",
                      "frame_loop_stall", "control_thread_stall", "disconnect", "misbehave", "gamepad",
                      "select_vehicle", "client_data", "operator_misbehave"});
    TimelineEvent event;
    event.mark = read_.mark(item);
    event.at = read_.duration(read_.require(item, "at", "timeline event"));
    if (event.at < previous) {
      read_.fail(item["at"], "event at " + format_time(event.at) + " is before the previous one at " +
                                 format_time(previous) + " (the timeline must be in time order)");
    }
    if (event.at > scenario_.duration) read_.fail(item["at"], "event after the end of the run (duration " + format_time(scenario_.duration) + ")");
    previous = event.at;
    if (item["name"]) {
      event.name = read_.text(item["name"]);
      if (!names.insert(event.name).second) read_.fail(item["name"], "duplicate event name '" + event.name + "'");
    }
    action(item, event);
    scenario_.timeline.push_back(std::move(event));
  }
}

void Parser::action(const YAML::Node& item, TimelineEvent& event) {
  check_one_action(item);
  if (const YAML::Node n = item["impair"]) {
    event.action = impair_action(n, item["ramp"], event);
  } else if (const YAML::Node n = item["outage"]) {
    event.action = outage_action(n, event);
  } else if (item["camera_stall"] || item["camera_unstall"]) {
    event.action = camera_stall_action(item, event);
  } else if (const YAML::Node n = item["frame_loop_stall"]) {
    read_.check_keys(n, "frame_loop_stall", {"vehicle", "for"});
    FrameLoopStall stall{vehicle_of(n, "frame_loop_stall"), read_.duration(read_.require(n, "for", "frame_loop_stall"))};
    event.label = "frame loop stall " + stall.vehicle + " " + format_time(stall.duration);
    event.action = stall;
  } else if (const YAML::Node n = item["control_thread_stall"]) {
    read_.check_keys(n, "control_thread_stall", {"vehicle", "for"});
    ControlThreadStall stall{vehicle_of(n, "control_thread_stall"), read_.duration(read_.require(n, "for", "control_thread_stall"))};
    event.label = "control thread stall " + stall.vehicle + " " + format_time(stall.duration);
    event.action = stall;
  } else if (const YAML::Node n = item["disconnect"]) {
    event.action = disconnect_action(n, event);
  } else if (const YAML::Node n = item["misbehave"]) {
    event.action = misbehave_action(n, event);
  } else if (const YAML::Node n = item["gamepad"]) {
    event.action = gamepad_action(n, event);
  } else if (const YAML::Node n = item["select_vehicle"]) {
    event.action = select_vehicle_action(n, event);
  } else if (const YAML::Node n = item["client_data"]) {
    event.action = client_data(n, event);
  } else if (const YAML::Node n = item["operator_misbehave"]) {
    event.action = operator_misbehave_action(n, event);
  }
}

// `at` and `name` say when and what to call it; `ramp` is a modifier of impair: anything else
// is an action, and an event with two would leave the reader guessing which one runs.
void Parser::check_one_action(const YAML::Node& item) {
  int actions = 0;
  for (const auto& entry : item) {
    const std::string key = entry.first.as<std::string>();
    if (key != "at" && key != "name" && key != "ramp") ++actions;
  }
  if (actions != 1) read_.fail(item, "a timeline event needs exactly one action (impair, outage, camera_stall, …)");
  if (item["ramp"] && !item["impair"]) read_.fail(item["ramp"], "ramp only applies to impair");
}

SetImpairments Parser::impair_action(const YAML::Node& n, const YAML::Node& ramp, TimelineEvent& event) {
  SetImpairments set;
  set.vehicle = vehicle_of(n, "impair");
  set.direction = direction_of(n);
  set.patch = impairments(n, true);
  if (ramp) set.ramp = read_.duration(ramp);
  event.label = "impair " + set.vehicle + " " + std::string(direction_name(set.direction)) +
                (set.ramp > Micros{0} ? " (ramp " + format_time(set.ramp) + ")" : "");
  return set;
}

LinkOutage Parser::outage_action(const YAML::Node& n, TimelineEvent& event) {
  read_.check_keys(n, "outage", {"vehicle", "direction", "for"});
  LinkOutage outage{vehicle_of(n, "outage"), direction_of(n), read_.duration(read_.require(n, "for", "outage"))};
  event.label = "outage " + outage.vehicle + " " + std::string(direction_name(outage.direction)) + " for " + format_time(outage.duration);
  return outage;
}

// camera_stall and camera_unstall share their keys; only a stall may last (`for`).
CameraStall Parser::camera_stall_action(const YAML::Node& item, TimelineEvent& event) {
  const bool stalled = static_cast<bool>(item["camera_stall"]);
  const YAML::Node n = stalled ? item["camera_stall"] : item["camera_unstall"];
  read_.check_keys(n, "camera_stall", {"vehicle", "camera", "for"});
  CameraStall stall;
  stall.vehicle = vehicle_of(n, "camera_stall");
  stall.stalled = stalled;
  stall.camera = camera_of(n, *find_vehicle(stall.vehicle));
  if (n["for"]) {
    if (!stalled) read_.fail(n["for"], "camera_unstall takes no 'for'");
    stall.duration = read_.duration(n["for"]);
  }
  event.label = std::string(stalled ? "camera stall " : "camera unstall ") + stall.vehicle + "/" + stall.camera;
  return stall;
}

// The `camera` key of a camera action; may be left out when the vehicle has one camera.
std::string Parser::camera_of(const YAML::Node& n, const VehicleSpec& spec) {
  std::string camera;
  if (n["camera"]) {
    camera = read_.text(n["camera"]);
  } else if (spec.streamer.cameras.size() == 1) {
    camera = spec.streamer.cameras.front().name;
  } else {
    read_.fail(n, "name the camera");
  }
  std::vector<std::string> cameras;
  for (const CameraConfig& config : spec.streamer.cameras) cameras.push_back(config.name);
  if (std::find(cameras.begin(), cameras.end(), camera) == cameras.end()) {
    read_.fail(n["camera"], unknown_name("camera", camera, cameras, "vehicle '" + spec.name + "'"));
  }
  return camera;
}

// An in-process client drops its connection; an external one is closed by the Streamer.
// listener_down: the Streamer's vehicle port restarts, closed that long.
DisconnectVehicle Parser::disconnect_action(const YAML::Node& n, TimelineEvent& event) {
  read_.check_keys(n, "disconnect", {"vehicle", "listener_down"});
  DisconnectVehicle disconnect{vehicle_of(n, "disconnect")};
  if (n["listener_down"]) {
    disconnect.listener_down = read_.duration(n["listener_down"]);
    if (disconnect.listener_down <= Micros{0} || disconnect.listener_down > max_listener_down) {
      read_.fail(n["listener_down"], "listener_down: expected a duration above 0 and at most " + format_time(max_listener_down));
    }
  }
  event.label = "disconnect " + disconnect.vehicle;
  if (disconnect.listener_down > Micros{0}) event.label += " (listener down " + format_time(disconnect.listener_down) + ")";
  return disconnect;
}

// Only an in-process client can be told to misbehave.
SetMisbehaviour Parser::misbehave_action(const YAML::Node& n, TimelineEvent& event) {
  SetMisbehaviour set{vehicle_of(n, "misbehave"), {}};
  if (!find_vehicle(set.vehicle)->in_process_client) read_.fail(n, "misbehave needs an in-process client");
  misbehave(n, set.misbehave, /*targeted=*/true);
  // Second to the client's connection: a vehicle without an in-process client has none.
  if (n["second_connection"]) set.second_connection = read_.boolean(n["second_connection"]);
  event.label = "misbehave " + set.vehicle + (set.misbehave.any() ? "" : " (all off)") +
                (set.second_connection ? ", second connection" : "");
  return set;
}

// `unplug`, `replug`, or a script for the pad to play.
GamepadAction Parser::gamepad_action(const YAML::Node& n, TimelineEvent& event) {
  GamepadAction pad;
  if (n.IsScalar() && n.Scalar() == "unplug") {
    pad.kind = GamepadAction::Kind::unplug;
  } else if (n.IsScalar() && n.Scalar() == "replug") {
    pad.kind = GamepadAction::Kind::replug;
  } else {
    if (n.IsScalar() && n.Scalar() != "idle" && n.Scalar() != "drive") {
      read_.fail_unknown(n, "gamepad action", n.Scalar(), {"unplug", "replug", "idle", "drive"});
    }
    pad.kind = GamepadAction::Kind::script;
    pad.script = gamepad_script(n);
  }
  event.label = "gamepad " + (n.IsScalar() ? n.Scalar() : std::string("script"));
  return pad;
}

// A vehicle's name, or null / `none` to deselect.
SelectVehicle Parser::select_vehicle_action(const YAML::Node& n, TimelineEvent& event) {
  SelectVehicle select;
  if (!n.IsNull() && n.Scalar() != "none") {
    select.vehicle = read_.text(n);
    if (find_vehicle(*select.vehicle) == nullptr) read_.fail_unknown(n, "vehicle", *select.vehicle, vehicle_list());
  }
  event.label = "select vehicle " + select.vehicle.value_or("none");
  return select;
}

// `misbehave: {bad_response: missing_field}`: the names of misbehaviour.hpp, with _ or -.
BadResponse Parser::bad_response(const YAML::Node& node) {
  const std::string name = read_.text(node);
  if (const auto kind = parse_bad_response(name)) return *kind;
  read_.fail_unknown(node, "bad_response", name,
                     {"none", "missing_field", "wrong_type", "not_an_object", "ack_time_out_of_range", "eof_mid_frame"});
}

// Client data may name a vehicle the Player does not have: SPEC §4.2 has it warn and go on,
// so a file may send it (to test just that), with a warning in case it is a typo.
void Parser::warn_unknown_client_vehicle(const YAML::Node& node, const std::string& name, std::string_view effect) {
  const Mark at = read_.mark(node);
  std::string text = read_.file() + ":" + std::to_string(at.line) + ":" + std::to_string(at.column) +
                     ": client data names vehicle '" + name + "', which the world does not have (the Player warns; " +
                     std::string(effect) + ")";
  if (const auto close = closest_name(name, vehicle_list())) text += ": did you mean '" + *close + "'?";
  scenario_.warnings.push_back(std::move(text));
}

ClientDataAction Parser::client_data(const YAML::Node& n, TimelineEvent& event) {
  read_.check_keys(n, "client_data", {"source", "active_vehicle", "vehicles", "every", "until"});
  ClientDataAction data;
  const std::string source = n["source"] ? read_.text(n["source"]) : "plugin";
  if (source == "plugin") data.source = ClientSource::plugin;
  else if (source == "webview") data.source = ClientSource::webview;
  else if (source == "tcp") data.source = ClientSource::tcp;
  else read_.fail_unknown(n["source"], "source", source, {"plugin", "webview", "tcp"});
  if (n["active_vehicle"]) {
    data.active_vehicle = read_.text(n["active_vehicle"]);
    if (find_vehicle(*data.active_vehicle) == nullptr) {
      warn_unknown_client_vehicle(n["active_vehicle"], *data.active_vehicle, "active_vehicle: no vehicle is active then");
    }
  }
  if (const YAML::Node vehicles = n["vehicles"]) {
    if (!vehicles.IsMap()) read_.fail(vehicles, "vehicles: expected a mapping vehicle → entry");
    for (const auto& item : vehicles) {
      const std::string name = item.first.as<std::string>();
      if (find_vehicle(name) == nullptr) warn_unknown_client_vehicle(item.first, name, "its entry is ignored");
      const YAML::Node entry = item.second;
      read_.check_keys(entry, "client_data entry", {"user_data", "disable_gamepad", "echo"});
      ClientDataAction::Entry out;
      if (entry["user_data"]) out.user_data_json = read_.json(entry["user_data"]);
      if (entry["disable_gamepad"]) out.disable_gamepad = read_.boolean(entry["disable_gamepad"]);
      if (entry["echo"]) {
        const std::string echo = read_.text(entry["echo"]);
        if (echo == "none") out.echo = ClientDataAction::Echo::none;
        else if (echo == "latest") out.echo = ClientDataAction::Echo::latest;
        else if (echo == "corrupt") out.echo = ClientDataAction::Echo::corrupt;
        else read_.fail_unknown(entry["echo"], "echo", echo, {"none", "latest", "corrupt"});
        if (data.source == ClientSource::webview && out.echo != ClientDataAction::Echo::none) {
          read_.fail(entry["echo"], "the web view sends no pair (the Player injects it, SPEC §4.2)");
        }
      }
      data.vehicles[name] = out;
    }
  }
  if (n["every"]) {
    data.every = read_.duration(n["every"]);
    if (data.every > Micros{0} && data.every < parse_limits().min_every) {
      read_.fail(n["every"], "every " + format_time(data.every) + " is faster than the floor, " +
                                 format_time(parse_limits().min_every) + " (at most 1 000 client data events a second)");
    }
  }
  if (n["until"]) {
    if (data.every <= Micros{0}) read_.fail(n["until"], "until needs every");
    data.until = read_.duration(n["until"]);
    if (*data.until < event.at) read_.fail(n["until"], "until is before the event");
  }
  event.label = "client data (" + source + ")" + (data.every > Micros{0} ? " every " + format_time(data.every) : "");
  return data;
}

}  // namespace ocp::scenario
