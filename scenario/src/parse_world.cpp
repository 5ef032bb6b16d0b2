// Scenario files: the `world` section (vehicles, links, timers, misbehaviours, gamepad).
#include "parser.hpp"

#include <filesystem>

#include "ocp/delivery_trace.hpp"
#include "scenario/parse.hpp"

namespace ocp::scenario {

void Parser::world(const YAML::Node& node) {
  read_.check_keys(node, "world", {"fleet", "player", "gamepad", "vehicles", "vehicle_pipe_delay",
                                   "reconnect_backoff", "operator_client"});
  WorldConfig& config = scenario_.world;
  const YAML::Node vehicles = read_.require(node, "vehicles", "world");
  if (!vehicles.IsSequence() || vehicles.size() == 0) read_.fail(vehicles, "world.vehicles: expected a non-empty list");
  for (const auto& item : vehicles) config.vehicles.push_back(vehicle(item));
  config.player.fleet = node["fleet"] ? read_.boolean(node["fleet"]) : config.vehicles.size() > 1;
  if (!config.player.fleet && config.vehicles.size() > 1 && !expects_refusal_) {
    read_.fail(node["fleet"], "several vehicles need fleet: true (SPEC §7)");
  }
  if (node["player"]) player(node["player"]);
  if (node["gamepad"]) scenario_.gamepad = gamepad_script(node["gamepad"]);
  if (node["vehicle_pipe_delay"]) config.vehicle_pipe_delay = read_.duration(node["vehicle_pipe_delay"]);
  if (node["reconnect_backoff"]) config.reconnect_backoff = read_.duration(node["reconnect_backoff"]);
  if (node["operator_client"]) operator_client(node["operator_client"]);
}

void Parser::player(const YAML::Node& node) {
  read_.check_keys(node, "world.player", {"frame_rate_hz", "no_feedback_timeout", "ping_period"});
  PlayerConfig& player = scenario_.world.player;
  if (node["frame_rate_hz"]) player.frame_rate_hz = read_.number(node["frame_rate_hz"], 1, 100);
  if (node["no_feedback_timeout"]) player.no_feedback_timeout = read_.duration(node["no_feedback_timeout"]);
  if (node["ping_period"]) player.ping_period = read_.duration(node["ping_period"]);
}

VehicleSpec Parser::vehicle(const YAML::Node& node) {
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
  check_replayed_routes(spec, node);
  if (node["misbehave"]) misbehave(node["misbehave"], spec.client.misbehave);
  if (spec.monitor && node["misbehave"]) read_.fail(node["misbehave"], "a monitor vehicle has no control path to misbehave on");
  return spec;
}

void Parser::misbehave(const YAML::Node& node, Misbehaviour& m, bool targeted) {
  if (targeted) {
    read_.check_keys(node, "misbehave", {"vehicle", "stop_echo", "corrupt_mac", "delay_responses", "oversized_frames",
                                         "ack_through_double", "malformed_json", "silent", "bad_response", "second_connection"});
  } else {
    read_.check_keys(node, "misbehave", {"stop_echo", "corrupt_mac", "delay_responses", "oversized_frames",
                                         "ack_through_double", "malformed_json", "silent", "bad_response"});
  }
  if (node["stop_echo"]) m.stop_echo = read_.boolean(node["stop_echo"]);
  if (node["corrupt_mac"]) m.corrupt_mac = read_.boolean(node["corrupt_mac"]);
  if (node["delay_responses"]) m.delay_responses = read_.duration(node["delay_responses"]);
  if (node["oversized_frames"]) m.oversized_frames = read_.boolean(node["oversized_frames"]);
  if (node["ack_through_double"]) m.ack_through_double = read_.boolean(node["ack_through_double"]);
  if (node["malformed_json"]) m.malformed_json = read_.boolean(node["malformed_json"]);
  if (node["silent"]) m.silent = read_.boolean(node["silent"]);
  if (node["bad_response"]) m.bad_response = bad_response(node["bad_response"]);   // parse_timeline.cpp
}

// `targeted`: the timeline's impair action, which also names vehicle and direction.
ImpairmentPatch Parser::impairments(const YAML::Node& node, bool targeted) {
  if (targeted) {
    read_.check_keys(node, "impair",
                     {"vehicle", "direction", "delay", "jitter", "jitter_kind", "loss", "burst_loss",
                      "bandwidth_bps", "queue_limit_bytes", "queue_limit_packets", "trace", "replay", "duplicate",
                      "reorder", "reorder_extra_delay", "down"});
  } else {
    read_.check_keys(node, "impairments",
                     {"delay", "jitter", "jitter_kind", "loss", "burst_loss", "bandwidth_bps",
                      "queue_limit_bytes", "queue_limit_packets", "trace", "replay", "duplicate", "reorder",
                      "reorder_extra_delay", "down"});
  }
  ImpairmentPatch p;
  if (node["delay"]) p.delay = read_.duration(node["delay"]);
  if (node["jitter"]) p.jitter = read_.duration(node["jitter"]);
  if (node["jitter_kind"]) {
    const std::string kind = read_.text(node["jitter_kind"]);
    if (kind == "none") p.jitter_kind = Impairments::JitterKind::none;
    else if (kind == "uniform") p.jitter_kind = Impairments::JitterKind::uniform;
    else if (kind == "normal") p.jitter_kind = Impairments::JitterKind::normal;
    else read_.fail_unknown(node["jitter_kind"], "jitter_kind", kind, {"none", "uniform", "normal"});
  }
  if (node["loss"]) p.loss = read_.number(node["loss"], 0, 1);
  if (node["duplicate"]) p.duplicate = read_.number(node["duplicate"], 0, 1);
  if (node["reorder"]) p.reorder = read_.number(node["reorder"], 0, 1);
  if (node["reorder_extra_delay"]) p.reorder_extra_delay = read_.duration(node["reorder_extra_delay"]);
  if (node["bandwidth_bps"]) p.bandwidth_bps = read_.number(node["bandwidth_bps"], 0, 1e12);
  if (node["queue_limit_bytes"]) p.queue_limit_bytes = read_.integer(node["queue_limit_bytes"]);
  if (node["queue_limit_packets"]) p.queue_limit_packets = read_.integer(node["queue_limit_packets"]);
  if (node["trace"]) {
    // The trace replaces the bandwidth cap; having both would leave one silently unused.
    if (p.bandwidth_bps && *p.bandwidth_bps > 0) {
      read_.fail(node["trace"], "trace and bandwidth_bps exclude each other: the trace is the capacity");
    }
    p.trace = delivery_trace(node["trace"]);
  }
  if (node["replay"]) p.replay = link_recording(node["replay"], node);
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

std::shared_ptr<const DeliveryTrace> Parser::delivery_trace(const YAML::Node& node) {
  return named_file(node, "trace", "a file name", delivery_traces_);
}

Controller Parser::controller(const YAML::Node& node) {
  // The recording text format's field syntax ("a=1 right_trigger=0.2"), one state.
  const std::string fields = read_.text(node);
  auto parsed = parse_recording("0 " + fields);
  if (!parsed || parsed->states.empty()) {
    read_.fail(node, "bad controller '" + fields + "': " + (parsed ? "empty" : parsed.error().detail));
  }
  return parsed->states.front().controller;
}

GamepadScriptSetting Parser::gamepad_script(const YAML::Node& node) {
  GamepadScriptSetting setting;
  if (node.IsScalar()) {
    const std::string name = node.Scalar();
    if (name == "idle") setting.kind = GamepadScriptSetting::Kind::idle;
    else if (name == "drive") setting.kind = GamepadScriptSetting::Kind::drive;
    else read_.fail_unknown(node, "gamepad script (idle, drive, {constant: …} or {waveform: …})", name, {"idle", "drive"});
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
      std::vector<std::string> axes;
      for (int i = 0; i <= static_cast<int>(GamepadAxis::right_trigger); ++i) {
        axes.emplace_back(gamepad_axis_name(static_cast<GamepadAxis>(i)));
        if (axes.back() == axis) {
          sine.axis = static_cast<GamepadAxis>(i);
          found = true;
        }
      }
      if (!found) read_.fail_unknown(item["axis"], "axis", axis, axes);
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

}  // namespace ocp::scenario
