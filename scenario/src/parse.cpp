// Scenario file → Scenario (the format: docs/scenarios.md, scenario/scenario.schema.json).
// One pass over the YAML tree; every check fails with the offending node's line and column.
#include "scenario/parse.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "yaml_read.hpp"

namespace ocp::scenario {
namespace {

std::string format_time(Micros time) {
  const auto us = time.count();
  if (us % 1'000'000 == 0) return std::to_string(us / 1'000'000) + "s";
  if (us % 1000 == 0) return std::to_string(us / 1000) + "ms";
  return std::to_string(us) + "us";
}

class Parser {
 public:
  Parser(std::string path) : read_(path) { scenario_.path = std::move(path); }

  Scenario parse(const std::string& text) {
    YAML::Node root;
    try {
      root = YAML::Load(text);
    } catch (const YAML::ParserException& error) {
      throw ScenarioError(read_.file(), error.mark.line + 1, error.mark.column + 1, error.msg);
    }
    if (!root || root.IsNull()) throw ScenarioError(read_.file(), 1, 1, "empty scenario file");
    read_.check_keys(root, "scenario", {"description", "seed", "duration", "world", "timeline", "expect"});
    scenario_.name = std::filesystem::path(scenario_.path).stem().string();
    if (root["description"]) scenario_.description = read_.text(root["description"]);
    if (root["seed"]) scenario_.seed = read_.integer(root["seed"]);
    scenario_.duration = read_.duration(read_.require(root, "duration", "scenario"));
    if (scenario_.duration <= Micros{0}) read_.fail(root["duration"], "duration must be > 0");
    world(read_.require(root, "world", "scenario"));
    if (root["timeline"]) timeline(root["timeline"]);
    expectations(read_.require(root, "expect", "scenario"));
    return std::move(scenario_);
  }

 private:
  // --- world ----------------------------------------------------------------------------
  void world(const YAML::Node& node) {
    read_.check_keys(node, "world", {"fleet", "player", "gamepad", "vehicles", "vehicle_pipe_delay",
                                     "reconnect_backoff"});
    WorldConfig& config = scenario_.world;
    const YAML::Node vehicles = read_.require(node, "vehicles", "world");
    if (!vehicles.IsSequence() || vehicles.size() == 0) read_.fail(vehicles, "world.vehicles: expected a non-empty list");
    for (const auto& item : vehicles) config.vehicles.push_back(vehicle(item));
    config.player.fleet = node["fleet"] ? read_.boolean(node["fleet"]) : config.vehicles.size() > 1;
    if (!config.player.fleet && config.vehicles.size() > 1) {
      read_.fail(node["fleet"], "several vehicles need fleet: true (SPEC §7)");
    }
    if (node["player"]) player(node["player"]);
    if (node["gamepad"]) scenario_.gamepad = gamepad_script(node["gamepad"]);
    if (node["vehicle_pipe_delay"]) config.vehicle_pipe_delay = read_.duration(node["vehicle_pipe_delay"]);
    if (node["reconnect_backoff"]) config.reconnect_backoff = read_.duration(node["reconnect_backoff"]);
  }

  void player(const YAML::Node& node) {
    read_.check_keys(node, "world.player", {"frame_rate_hz", "no_feedback_timeout", "ping_period"});
    PlayerConfig& player = scenario_.world.player;
    if (node["frame_rate_hz"]) player.frame_rate_hz = read_.number(node["frame_rate_hz"], 1, 100);
    if (node["no_feedback_timeout"]) player.no_feedback_timeout = read_.duration(node["no_feedback_timeout"]);
    if (node["ping_period"]) player.ping_period = read_.duration(node["ping_period"]);
  }

  VehicleSpec vehicle(const YAML::Node& node) {
    read_.check_keys(node, "vehicle",
                     {"name", "monitor", "in_process_client", "cameras", "link", "to_streamer",
                      "to_player", "misbehave", "latency_limit", "no_control_timeout",
                      "vehicle_read_timeout", "camera_drop_timeout", "streamer_slow_threshold",
                      "control_period", "frame_rate_hz", "control_queue_limit",
                      "control_queue_max_age", "ack_time_offset"});
    VehicleSpec spec;
    spec.name = read_.text(read_.require(node, "name", "vehicle"));
    for (const VehicleSpec& other : scenario_.world.vehicles) {
      if (other.name == spec.name) read_.fail(node["name"], "duplicate vehicle name '" + spec.name + "'");
    }
    StreamerConfig& s = spec.streamer;
    if (node["monitor"]) spec.monitor = read_.boolean(node["monitor"]);
    if (node["in_process_client"]) spec.in_process_client = read_.boolean(node["in_process_client"]);
    if (node["latency_limit"]) s.latency_limit = read_.duration(node["latency_limit"]);
    if (node["no_control_timeout"]) s.no_control_timeout = read_.duration(node["no_control_timeout"]);
    if (node["vehicle_read_timeout"]) s.vehicle_read_timeout = read_.duration(node["vehicle_read_timeout"]);
    if (node["camera_drop_timeout"]) s.camera_drop_timeout = read_.duration(node["camera_drop_timeout"]);
    if (node["streamer_slow_threshold"]) s.streamer_slow_threshold = read_.duration(node["streamer_slow_threshold"]);
    if (node["control_period"]) s.control_period = read_.duration(node["control_period"]);
    if (s.control_period <= Micros{0}) read_.fail(node["control_period"], "control_period must be > 0");
    if (node["frame_rate_hz"]) s.frame_rate_hz = read_.number(node["frame_rate_hz"], 0.1, 1000);
    if (node["control_queue_limit"]) s.control_queue_limit = read_.integer(node["control_queue_limit"]);
    if (node["control_queue_max_age"]) s.control_queue_max_age = read_.duration(node["control_queue_max_age"]);
    if (node["ack_time_offset"]) s.ack_time_offset = read_.integer(node["ack_time_offset"]);
    if (node["cameras"]) {
      const YAML::Node cameras = node["cameras"];
      if (!cameras.IsSequence()) read_.fail(cameras, "cameras: expected a list");
      s.cameras.clear();
      for (const auto& item : cameras) {
        read_.check_keys(item, "camera", {"name", "fps", "drop_detector", "frame_size_bytes"});
        CameraConfig camera;
        camera.name = read_.text(read_.require(item, "name", "camera"));
        if (item["fps"]) camera.fps = read_.number(item["fps"], 0.1, 1000);
        if (item["drop_detector"]) camera.drop_detector = read_.boolean(item["drop_detector"]);
        if (item["frame_size_bytes"]) camera.frame_size_bytes = static_cast<std::uint32_t>(read_.integer(item["frame_size_bytes"]));
        s.cameras.push_back(camera);
      }
    }
    if (node["link"]) {
      const ImpairmentPatch both = impairments(node["link"]);
      spec.to_streamer = apply_patch(spec.to_streamer, both);
      spec.to_player = apply_patch(spec.to_player, both);
    }
    if (node["to_streamer"]) spec.to_streamer = apply_patch(spec.to_streamer, impairments(node["to_streamer"]));
    if (node["to_player"]) spec.to_player = apply_patch(spec.to_player, impairments(node["to_player"]));
    if (node["misbehave"]) misbehave(node["misbehave"], spec.client.misbehave);
    if (spec.monitor && node["misbehave"]) read_.fail(node["misbehave"], "a monitor vehicle has no control path to misbehave on");
    return spec;
  }

  void misbehave(const YAML::Node& node, Misbehaviour& m) {
    read_.check_keys(node, "misbehave", {"stop_echo", "corrupt_mac", "delay_responses", "oversized_frames",
                                         "ack_through_double", "malformed_json", "silent"});
    if (node["stop_echo"]) m.stop_echo = read_.boolean(node["stop_echo"]);
    if (node["corrupt_mac"]) m.corrupt_mac = read_.boolean(node["corrupt_mac"]);
    if (node["delay_responses"]) m.delay_responses = read_.duration(node["delay_responses"]);
    if (node["oversized_frames"]) m.oversized_frames = read_.boolean(node["oversized_frames"]);
    if (node["ack_through_double"]) m.ack_through_double = read_.boolean(node["ack_through_double"]);
    if (node["malformed_json"]) m.malformed_json = read_.boolean(node["malformed_json"]);
    if (node["silent"]) m.silent = read_.boolean(node["silent"]);
  }

  // `targeted`: the timeline's impair action, which also names vehicle and direction.
  ImpairmentPatch impairments(const YAML::Node& node, bool targeted = false) {
    if (targeted) {
      read_.check_keys(node, "impair",
                       {"vehicle", "direction", "delay", "jitter", "jitter_kind", "loss", "burst_loss",
                        "bandwidth_bps", "queue_limit_bytes", "duplicate", "reorder",
                        "reorder_extra_delay", "down"});
    } else {
      read_.check_keys(node, "impairments",
                       {"delay", "jitter", "jitter_kind", "loss", "burst_loss", "bandwidth_bps",
                        "queue_limit_bytes", "duplicate", "reorder", "reorder_extra_delay", "down"});
    }
    ImpairmentPatch p;
    if (node["delay"]) p.delay = read_.duration(node["delay"]);
    if (node["jitter"]) p.jitter = read_.duration(node["jitter"]);
    if (node["jitter_kind"]) {
      const std::string kind = read_.text(node["jitter_kind"]);
      if (kind == "none") p.jitter_kind = Impairments::JitterKind::none;
      else if (kind == "uniform") p.jitter_kind = Impairments::JitterKind::uniform;
      else if (kind == "normal") p.jitter_kind = Impairments::JitterKind::normal;
      else read_.fail(node["jitter_kind"], "jitter_kind: expected none, uniform or normal");
    }
    if (node["loss"]) p.loss = read_.number(node["loss"], 0, 1);
    if (node["duplicate"]) p.duplicate = read_.number(node["duplicate"], 0, 1);
    if (node["reorder"]) p.reorder = read_.number(node["reorder"], 0, 1);
    if (node["reorder_extra_delay"]) p.reorder_extra_delay = read_.duration(node["reorder_extra_delay"]);
    if (node["bandwidth_bps"]) p.bandwidth_bps = read_.number(node["bandwidth_bps"], 0, 1e12);
    if (node["queue_limit_bytes"]) p.queue_limit_bytes = read_.integer(node["queue_limit_bytes"]);
    if (node["down"]) p.down = read_.boolean(node["down"]);
    if (const YAML::Node burst = node["burst_loss"]) {
      if (burst.IsScalar()) {
        p.burst_loss = read_.boolean(burst);
      } else {
        read_.check_keys(burst, "burst_loss", {"good_to_bad", "bad_to_good", "loss_in_good", "loss_in_bad"});
        p.burst_loss = true;
        if (burst["good_to_bad"]) p.good_to_bad = read_.number(burst["good_to_bad"], 0, 1);
        if (burst["bad_to_good"]) p.bad_to_good = read_.number(burst["bad_to_good"], 0, 1);
        if (burst["loss_in_good"]) p.loss_in_good = read_.number(burst["loss_in_good"], 0, 1);
        if (burst["loss_in_bad"]) p.loss_in_bad = read_.number(burst["loss_in_bad"], 0, 1);
      }
    }
    return p;
  }

  Controller controller(const YAML::Node& node) {
    // The recording text format's field syntax ("a=1 right_trigger=0.2"), one state.
    const std::string fields = read_.text(node);
    auto parsed = parse_recording("0 " + fields);
    if (!parsed || parsed->states.empty()) {
      read_.fail(node, "bad controller '" + fields + "': " + (parsed ? "empty" : parsed.error().detail));
    }
    return parsed->states.front().controller;
  }

  GamepadScriptSetting gamepad_script(const YAML::Node& node) {
    GamepadScriptSetting setting;
    if (node.IsScalar()) {
      const std::string name = node.Scalar();
      if (name == "idle") setting.kind = GamepadScriptSetting::Kind::idle;
      else if (name == "drive") setting.kind = GamepadScriptSetting::Kind::drive;
      else read_.fail(node, "gamepad: expected idle, drive, {constant: …} or {waveform: …}, got '" + name + "'");
      return setting;
    }
    read_.check_keys(node, "gamepad", {"constant", "waveform"});
    if (node["constant"]) {
      setting.kind = GamepadScriptSetting::Kind::constant;
      setting.constant = controller(node["constant"]);
    } else if (const YAML::Node wave = node["waveform"]) {
      setting.kind = GamepadScriptSetting::Kind::waveform;
      read_.check_keys(wave, "waveform", {"base", "waves"});
      if (wave["base"]) setting.waveform.base = controller(wave["base"]);
      const YAML::Node waves = read_.require(wave, "waves", "waveform");
      if (!waves.IsSequence()) read_.fail(waves, "waves: expected a list");
      for (const auto& item : waves) {
        read_.check_keys(item, "wave", {"axis", "amplitude", "period", "phase"});
        SineWave sine;
        const std::string axis = read_.text(read_.require(item, "axis", "wave"));
        bool found = false;
        for (int i = 0; i <= static_cast<int>(GamepadAxis::right_trigger); ++i) {
          if (gamepad_axis_name(static_cast<GamepadAxis>(i)) == axis) {
            sine.axis = static_cast<GamepadAxis>(i);
            found = true;
          }
        }
        if (!found) read_.fail(item["axis"], "unknown axis '" + axis + "'");
        if (item["amplitude"]) sine.amplitude = read_.number(item["amplitude"], -2, 2);
        if (item["period"]) sine.period = read_.duration(item["period"]);
        if (sine.period <= Micros{0}) read_.fail(item, "wave period must be > 0");
        if (item["phase"]) sine.phase_radians = read_.number(item["phase"], -100, 100);
        setting.waveform.waves.push_back(sine);
      }
    } else {
      read_.fail(node, "gamepad: expected constant or waveform");
    }
    return setting;
  }

  // --- timeline -------------------------------------------------------------------------
  const VehicleSpec* find_vehicle(const std::string& name) const {
    for (const VehicleSpec& spec : scenario_.world.vehicles) {
      if (spec.name == name) return &spec;
    }
    return nullptr;
  }

  // The `vehicle` key of an action; may be left out when the world has one vehicle.
  std::string vehicle_of(const YAML::Node& node, std::string_view what) {
    if (!node["vehicle"]) {
      if (scenario_.world.vehicles.size() == 1) return scenario_.world.vehicles.front().name;
      read_.fail(node, std::string(what) + ": name the vehicle (the world has several)");
    }
    const std::string name = read_.text(node["vehicle"]);
    if (find_vehicle(name) == nullptr) read_.fail(node["vehicle"], "unknown vehicle '" + name + "'");
    return name;
  }

  Direction direction_of(const YAML::Node& node) {
    if (!node["direction"]) return Direction::both;
    const std::string name = read_.text(node["direction"]);
    if (name == "both") return Direction::both;
    if (name == "to_streamer") return Direction::to_streamer;
    if (name == "to_player") return Direction::to_player;
    read_.fail(node["direction"], "direction: expected both, to_streamer or to_player");
  }

  void timeline(const YAML::Node& node) {
    if (!node.IsSequence()) read_.fail(node, "timeline: expected a list of events");
    SimTime previous{0};
    std::set<std::string> names;
    for (const auto& item : node) {
      read_.check_keys(item, "timeline event",
                       {"at", "name", "impair", "ramp", "outage", "camera_stall", "camera_unstall",
                        "frame_loop_stall", "control_thread_stall", "disconnect", "gamepad",
                        "select_vehicle", "client_data"});
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

  void action(const YAML::Node& item, TimelineEvent& event) {
    int actions = 0;
    for (const auto& entry : item) {
      const std::string key = entry.first.as<std::string>();
      if (key != "at" && key != "name" && key != "ramp") ++actions;
    }
    if (actions != 1) read_.fail(item, "a timeline event needs exactly one action (impair, outage, camera_stall, …)");
    if (item["ramp"] && !item["impair"]) read_.fail(item["ramp"], "ramp only applies to impair");

    if (const YAML::Node n = item["impair"]) {
      SetImpairments set;
      set.vehicle = vehicle_of(n, "impair");
      set.direction = direction_of(n);
      set.patch = impairments(n, true);
      if (item["ramp"]) set.ramp = read_.duration(item["ramp"]);
      event.label = "impair " + set.vehicle + " " + std::string(direction_name(set.direction)) +
                    (set.ramp > Micros{0} ? " (ramp " + format_time(set.ramp) + ")" : "");
      event.action = set;
    } else if (const YAML::Node n = item["outage"]) {
      read_.check_keys(n, "outage", {"vehicle", "direction", "for"});
      LinkOutage outage{vehicle_of(n, "outage"), direction_of(n), read_.duration(read_.require(n, "for", "outage"))};
      event.label = "outage " + outage.vehicle + " " + std::string(direction_name(outage.direction)) + " for " + format_time(outage.duration);
      event.action = outage;
    } else if (item["camera_stall"] || item["camera_unstall"]) {
      const bool stalled = static_cast<bool>(item["camera_stall"]);
      const YAML::Node n = stalled ? item["camera_stall"] : item["camera_unstall"];
      read_.check_keys(n, "camera_stall", {"vehicle", "camera", "for"});
      CameraStall stall;
      stall.vehicle = vehicle_of(n, "camera_stall");
      stall.stalled = stalled;
      const VehicleSpec& spec = *find_vehicle(stall.vehicle);
      if (n["camera"]) {
        stall.camera = read_.text(n["camera"]);
      } else if (spec.streamer.cameras.size() == 1) {
        stall.camera = spec.streamer.cameras.front().name;
      } else {
        read_.fail(n, "name the camera");
      }
      const bool known = std::any_of(spec.streamer.cameras.begin(), spec.streamer.cameras.end(),
                                     [&](const CameraConfig& c) { return c.name == stall.camera; });
      if (!known) read_.fail(n["camera"], "vehicle '" + stall.vehicle + "' has no camera '" + stall.camera + "'");
      if (n["for"]) {
        if (!stalled) read_.fail(n["for"], "camera_unstall takes no 'for'");
        stall.duration = read_.duration(n["for"]);
      }
      event.label = std::string(stalled ? "camera stall " : "camera unstall ") + stall.vehicle + "/" + stall.camera;
      event.action = stall;
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
      read_.check_keys(n, "disconnect", {"vehicle"});
      DisconnectVehicle disconnect{vehicle_of(n, "disconnect")};
      if (!find_vehicle(disconnect.vehicle)->in_process_client) read_.fail(n, "disconnect needs an in-process client");
      event.label = "disconnect " + disconnect.vehicle;
      event.action = disconnect;
    } else if (const YAML::Node n = item["gamepad"]) {
      GamepadAction pad;
      if (n.IsScalar() && n.Scalar() == "unplug") {
        pad.kind = GamepadAction::Kind::unplug;
      } else if (n.IsScalar() && n.Scalar() == "replug") {
        pad.kind = GamepadAction::Kind::replug;
      } else {
        pad.kind = GamepadAction::Kind::script;
        pad.script = gamepad_script(n);
      }
      event.label = "gamepad " + (n.IsScalar() ? n.Scalar() : std::string("script"));
      event.action = pad;
    } else if (const YAML::Node n = item["select_vehicle"]) {
      SelectVehicle select;
      if (!n.IsNull() && n.Scalar() != "none") {
        select.vehicle = read_.text(n);
        if (find_vehicle(*select.vehicle) == nullptr) read_.fail(n, "unknown vehicle '" + *select.vehicle + "'");
      }
      event.label = "select vehicle " + select.vehicle.value_or("none");
      event.action = select;
    } else if (const YAML::Node n = item["client_data"]) {
      event.action = client_data(n, event);
    }
  }

  ClientDataAction client_data(const YAML::Node& n, TimelineEvent& event) {
    read_.check_keys(n, "client_data", {"source", "active_vehicle", "vehicles", "every", "until"});
    ClientDataAction data;
    const std::string source = n["source"] ? read_.text(n["source"]) : "plugin";
    if (source == "plugin") data.source = ClientSource::plugin;
    else if (source == "webview") data.source = ClientSource::webview;
    else if (source == "tcp") data.source = ClientSource::tcp;
    else read_.fail(n["source"], "source: expected plugin, webview or tcp");
    if (n["active_vehicle"]) {
      data.active_vehicle = read_.text(n["active_vehicle"]);
      if (find_vehicle(*data.active_vehicle) == nullptr) read_.fail(n["active_vehicle"], "unknown vehicle '" + *data.active_vehicle + "'");
    }
    if (const YAML::Node vehicles = n["vehicles"]) {
      if (!vehicles.IsMap()) read_.fail(vehicles, "vehicles: expected a mapping vehicle → entry");
      for (const auto& item : vehicles) {
        const std::string name = item.first.as<std::string>();
        if (find_vehicle(name) == nullptr) read_.fail(item.first, "unknown vehicle '" + name + "'");
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
          else read_.fail(entry["echo"], "echo: expected none, latest or corrupt");
          if (data.source == ClientSource::webview && out.echo != ClientDataAction::Echo::none) {
            read_.fail(entry["echo"], "the web view sends no pair (the Player injects it, SPEC §4.2)");
          }
        }
        data.vehicles[name] = out;
      }
    }
    if (n["every"]) data.every = read_.duration(n["every"]);
    if (n["until"]) {
      if (data.every <= Micros{0}) read_.fail(n["until"], "until needs every");
      data.until = read_.duration(n["until"]);
      if (*data.until < event.at) read_.fail(n["until"], "until is before the event");
    }
    event.label = "client data (" + source + ")" + (data.every > Micros{0} ? " every " + format_time(data.every) : "");
    return data;
  }

  // --- expectations ---------------------------------------------------------------------
  void expectations(const YAML::Node& node) {
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
          read_.fail(item, "unknown invariant '" + name +
                               "' (known: default_controller_during_control_fault, no_stale_pair_after_reconnect)");
        }
        scenario_.expectations.push_back({"invariant " + name, read_.mark(item), expectation});
      }
    }
    if (scenario_.expectations.empty()) read_.fail(node, "expect: no expectation (a scenario must check something)");
  }

  // `after`: an event name or a time.
  std::pair<SimTime, std::string> anchor(const YAML::Node& node) {
    const std::string text = read_.text(node);
    for (const TimelineEvent& event : scenario_.timeline) {
      if (!event.name.empty() && event.name == text) return {event.at, text};
    }
    try {
      return {parse_duration_text(text), text};
    } catch (const std::invalid_argument&) {
      read_.fail(node, "'" + text + "' names no timeline event (and is not a time)");
    }
  }

  void fault_expectation(const YAML::Node& node) {
    read_.check_keys(node, "fault expectation", {"fault", "vehicle", "raised", "cleared", "never", "from", "at", "active_on", "inactive_on"});
    const YAML::Node fault_node = read_.require(node, "fault", "fault expectation");
    const auto fault = parse_fault_identifier(read_.text(fault_node));
    if (!fault) read_.fail(fault_node, "unknown fault '" + fault_node.Scalar() + "' (SPEC §6 identifiers)");
    const std::string fault_name(fault_identifier(*fault));
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
      if (!read_.boolean(node["never"])) read_.fail(node["never"], "never: only true makes sense");
      FaultNeverExpectation expectation{*fault, vehicle, SimTime{0}};
      std::string title = fault_name + " never raised" + (vehicle ? " on " + *vehicle : "");
      if (node["from"]) {
        std::string label;
        std::tie(expectation.from, label) = anchor(node["from"]);
        title += " from " + label;
      }
      scenario_.expectations.push_back({title, read_.mark(node), expectation});
      return;
    }
    if (edges) {
      if (!vehicle) {
        if (scenario_.world.vehicles.size() != 1) read_.fail(node, "name the vehicle (the world has several)");
        vehicle = scenario_.world.vehicles.front().name;
      }
      for (const char* key : {"raised", "cleared"}) {
        const YAML::Node edge = node[key];
        if (!edge) continue;
        read_.check_keys(edge, key, {"after", "within"});
        FaultEdgeExpectation expectation;
        expectation.fault = *fault;
        expectation.vehicle = *vehicle;
        expectation.raised = std::string(key) == "raised";
        std::tie(expectation.after, expectation.after_label) = anchor(read_.require(edge, "after", key));
        const YAML::Node within = read_.require(edge, "within", key);
        if (within.IsSequence()) {
          if (within.size() != 2) read_.fail(within, "within: expected [min, max] or one maximum");
          expectation.min = read_.duration(within[0]);
          expectation.max = read_.duration(within[1]);
          if (expectation.max < expectation.min) read_.fail(within, "within: max < min");
        } else {
          expectation.max = read_.duration(within);
        }
        const std::string window = expectation.min > Micros{0}
                                       ? "[" + format_time(expectation.min) + ", " + format_time(expectation.max) + "]"
                                       : format_time(expectation.max);
        scenario_.expectations.push_back(
            {fault_name + " " + key + " within " + window + " after " + expectation.after_label + " on " + *vehicle,
             read_.mark(edge), expectation});
      }
      return;
    }
    FaultStateExpectation expectation;
    expectation.fault = *fault;
    expectation.at = read_.duration(node["at"]);
    if (expectation.at > scenario_.duration) read_.fail(node["at"], "at is after the end of the run");
    auto names = [&](const char* key, std::vector<std::string>& out) {
      const YAML::Node list = node[key];
      if (!list) return;
      if (list.IsScalar() && list.Scalar() == "every_vehicle_but_active" && std::string(key) == "active_on") {
        expectation.every_vehicle_but_active = true;
        return;
      }
      if (!list.IsSequence()) read_.fail(list, std::string(key) + ": expected a list of vehicles");
      for (const auto& item : list) {
        const std::string name = read_.text(item);
        if (find_vehicle(name) == nullptr) read_.fail(item, "unknown vehicle '" + name + "'");
        out.push_back(name);
      }
    };
    names("active_on", expectation.active_on);
    names("inactive_on", expectation.inactive_on);
    if (!expectation.every_vehicle_but_active && expectation.active_on.empty() && expectation.inactive_on.empty()) {
      read_.fail(node, "at: say on which vehicles (active_on: [...], inactive_on: [...] or active_on: every_vehicle_but_active)");
    }
    std::string title = fault_name + " at " + format_time(expectation.at) + ": ";
    if (expectation.every_vehicle_but_active) title += "active on every vehicle but the active one";
    else {
      for (const auto& name : expectation.active_on) title += "active on " + name + " ";
      for (const auto& name : expectation.inactive_on) title += "inactive on " + name + " ";
      title.pop_back();
    }
    scenario_.expectations.push_back({title, read_.mark(node), expectation});
  }

  void delivery_expectation(const YAML::Node& node) {
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
      else read_.fail(controller, "controller: expected null, default, driving or any");
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

  void threshold_expectations(const YAML::Node& key, const YAML::Node& list) {
    static const std::set<std::string> metrics = {"latency_ms", "echo_delay_ms", "control_gap_ms",
                                                  "feedback_gap_ms", "lost_to_streamer", "lost_to_player"};
    std::string metric = read_.text(key);
    std::optional<std::string> vehicle;
    if (const auto brace = metric.find('{'); brace != std::string::npos) {
      if (metric.back() != '}') read_.fail(key, "metric{vehicle}: missing '}'");
      vehicle = metric.substr(brace + 1, metric.size() - brace - 2);
      metric = metric.substr(0, brace);
      if (find_vehicle(*vehicle) == nullptr) read_.fail(key, "unknown vehicle '" + *vehicle + "'");
    }
    if (metrics.count(metric) == 0) {
      read_.fail(key, "unknown metric '" + metric + "' (known: latency_ms, echo_delay_ms, control_gap_ms, "
                      "feedback_gap_ms, lost_to_streamer, lost_to_player)");
    }
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
        read_.fail(item, "unknown aggregate '" + t.aggregate + "' (avg, min, max, med, count, rate, p(N))");
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

  YamlReader read_;
  Scenario scenario_;
};

}  // namespace

Scenario parse_scenario(const std::string& text, const std::string& path) {
  try {
    return Parser(path).parse(text);
  } catch (const YAML::Exception& error) {
    // yaml-cpp's own conversions (a non-scalar key, …) carry a position too.
    throw ScenarioError(path, error.mark.line + 1, error.mark.column + 1, error.msg);
  }
}

Scenario load_scenario(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ScenarioError(path, 0, 0, "cannot read the file");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_scenario(text.str(), path);
}

}  // namespace ocp::scenario
