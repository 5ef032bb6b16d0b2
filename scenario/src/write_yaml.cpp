// Scenario → YAML (write.hpp). Built as a yaml-cpp node tree and emitted, so quoting is
// yaml-cpp's business; numbers are written in their shortest exact form, durations as the
// parser reads them, user data as the JSON it is (JSON is YAML).
#include "scenario/write.hpp"

#include <yaml-cpp/yaml.h>

#include <charconv>
#include <filesystem>
#include <sstream>

#include "ocp/delivery_trace.hpp"
#include "ocp/link_recording.hpp"
#include "vehicle_client/misbehaviour.hpp"

namespace ocp::scenario {

std::string duration_text(Micros time) {
  const auto us = time.count();
  if (us % 1'000'000 == 0) return std::to_string(us / 1'000'000) + "s";
  if (us % 1000 == 0) return std::to_string(us / 1000) + "ms";
  return std::to_string(us) + "us";
}

namespace {

std::string shortest_number(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

std::string_view jitter_kind_name(Impairments::JitterKind kind) {
  switch (kind) {
    case Impairments::JitterKind::none: return "none";
    case Impairments::JitterKind::uniform: return "uniform";
    case Impairments::JitterKind::normal: return "normal";
  }
  return "none";
}

// Every field of a whole setting (a vehicle's link at start).
// Absolute: the written file may live elsewhere than the scenario that named the trace.
std::string trace_file_text(const DeliveryTrace& trace) {
  return std::filesystem::absolute(trace.name()).lexically_normal().string();
}

std::string recording_file_text(const LinkRecording& recording) {
  return std::filesystem::absolute(recording.name()).lexically_normal().string();
}

YAML::Node impairments_node(const Impairments& in) {
  YAML::Node out;
  if (in.replay) {
    // A replayed direction uses nothing else (and the parser refuses the rest beside it).
    out["replay"] = recording_file_text(*in.replay);
    out["down"] = in.down;
    return out;
  }
  out["delay"] = duration_text(in.delay);
  out["jitter"] = duration_text(in.jitter);
  out["jitter_kind"] = std::string(jitter_kind_name(in.jitter_kind));
  out["loss"] = shortest_number(in.loss_probability);
  if (in.burst_loss) {
    YAML::Node burst;
    burst["good_to_bad"] = shortest_number(in.good_to_bad_probability);
    burst["bad_to_good"] = shortest_number(in.bad_to_good_probability);
    burst["loss_in_good"] = shortest_number(in.loss_in_good);
    burst["loss_in_bad"] = shortest_number(in.loss_in_bad);
    out["burst_loss"] = burst;
  } else {
    out["burst_loss"] = false;
  }
  out["bandwidth_bps"] = shortest_number(in.bandwidth_bits_per_second);
  out["queue_limit_bytes"] = in.queue_limit_bytes;
  if (in.trace) {
    out["trace"] = trace_file_text(*in.trace);
    out["queue_limit_packets"] = in.queue_limit_packets;
  }
  out["duplicate"] = shortest_number(in.duplicate_probability);
  out["reorder"] = shortest_number(in.reorder_probability);
  out["reorder_extra_delay"] = duration_text(in.reorder_extra_delay);
  out["down"] = in.down;
  return out;
}

// Only the fields a patch sets.
void patch_fields(YAML::Node& out, const ImpairmentPatch& p) {
  if (p.delay) out["delay"] = duration_text(*p.delay);
  if (p.jitter) out["jitter"] = duration_text(*p.jitter);
  if (p.jitter_kind) out["jitter_kind"] = std::string(jitter_kind_name(*p.jitter_kind));
  if (p.loss) out["loss"] = shortest_number(*p.loss);
  if (p.good_to_bad || p.bad_to_good || p.loss_in_good || p.loss_in_bad) {
    // The parser reads a burst_loss map as "burst loss on, with these parameters".
    YAML::Node burst;
    if (p.good_to_bad) burst["good_to_bad"] = shortest_number(*p.good_to_bad);
    if (p.bad_to_good) burst["bad_to_good"] = shortest_number(*p.bad_to_good);
    if (p.loss_in_good) burst["loss_in_good"] = shortest_number(*p.loss_in_good);
    if (p.loss_in_bad) burst["loss_in_bad"] = shortest_number(*p.loss_in_bad);
    out["burst_loss"] = burst;
  } else if (p.burst_loss) {
    out["burst_loss"] = *p.burst_loss;
  }
  if (p.bandwidth_bps) out["bandwidth_bps"] = shortest_number(*p.bandwidth_bps);
  if (p.queue_limit_bytes) out["queue_limit_bytes"] = *p.queue_limit_bytes;
  if (p.queue_limit_packets) out["queue_limit_packets"] = *p.queue_limit_packets;
  if (p.trace && *p.trace) out["trace"] = trace_file_text(**p.trace);
  if (p.replay && *p.replay) out["replay"] = recording_file_text(**p.replay);
  if (p.duplicate) out["duplicate"] = shortest_number(*p.duplicate);
  if (p.reorder) out["reorder"] = shortest_number(*p.reorder);
  if (p.reorder_extra_delay) out["reorder_extra_delay"] = duration_text(*p.reorder_extra_delay);
  if (p.down) out["down"] = *p.down;
}

void misbehave_fields(YAML::Node& out, const Misbehaviour& m) {
  out["stop_echo"] = m.stop_echo;
  out["corrupt_mac"] = m.corrupt_mac;
  out["delay_responses"] = duration_text(m.delay_responses);
  out["oversized_frames"] = m.oversized_frames;
  out["ack_through_double"] = m.ack_through_double;
  out["malformed_json"] = m.malformed_json;
  out["silent"] = m.silent;
  if (m.bad_response != BadResponse::none) {
    std::string name(bad_response_name(m.bad_response));
    for (char& c : name) c = c == '-' ? '_' : c;   // as scenario files write it
    out["bad_response"] = name;
  }
}

// The recording format's field syntax of one state ("a=1 left_x=0.5").
std::string controller_text(const Controller& controller) {
  Recording recording;
  recording.states.push_back({Micros{0}, controller});
  std::string text = format_recording(recording);
  // One line "<time> fields…": keep the fields.
  const auto line_end = text.find('\n');
  if (line_end != std::string::npos) text.resize(line_end);
  const auto space = text.find(' ');
  return space == std::string::npos ? std::string() : text.substr(space + 1);
}

YAML::Node gamepad_node(const GamepadScriptSetting& setting) {
  switch (setting.kind) {
    case GamepadScriptSetting::Kind::idle: return YAML::Node("idle");
    case GamepadScriptSetting::Kind::drive: return YAML::Node("drive");
    case GamepadScriptSetting::Kind::constant: {
      YAML::Node node;
      node["constant"] = controller_text(setting.constant);
      return node;
    }
    case GamepadScriptSetting::Kind::waveform: {
      YAML::Node wave;
      wave["base"] = controller_text(setting.waveform.base);
      for (const SineWave& sine : setting.waveform.waves) {
        YAML::Node item;
        item["axis"] = std::string(gamepad_axis_name(sine.axis));
        item["amplitude"] = shortest_number(sine.amplitude);
        item["period"] = duration_text(sine.period);
        item["phase"] = shortest_number(sine.phase_radians);
        wave["waves"].push_back(item);
      }
      YAML::Node node;
      node["waveform"] = wave;
      return node;
    }
  }
  return YAML::Node("idle");
}

YAML::Node vehicle_node(const VehicleSpec& spec) {
  YAML::Node out;
  const StreamerConfig& s = spec.streamer;
  out["name"] = spec.name;
  out["monitor"] = spec.monitor;
  out["in_process_client"] = spec.in_process_client;
  out["latency_limit"] = duration_text(s.latency_limit);
  out["no_control_timeout"] = duration_text(s.no_control_timeout);
  out["vehicle_read_timeout"] = duration_text(s.vehicle_read_timeout);
  out["camera_drop_timeout"] = duration_text(s.camera_drop_timeout);
  out["streamer_slow_threshold"] = duration_text(s.streamer_slow_threshold);
  out["control_period"] = duration_text(s.control_period);
  out["frame_rate_hz"] = shortest_number(s.frame_rate_hz);
  out["control_queue_limit"] = s.control_queue_limit;
  out["control_queue_max_age"] = duration_text(s.control_queue_max_age);
  if (s.ack_time_offset != 0) out["ack_time_offset"] = s.ack_time_offset;
  for (const CameraConfig& camera : s.cameras) {
    YAML::Node item;
    item["name"] = camera.name;
    item["fps"] = shortest_number(camera.fps);
    item["drop_detector"] = camera.drop_detector;
    item["frame_size_bytes"] = camera.frame_size_bytes;
    out["cameras"].push_back(item);
  }
  out["to_streamer"] = impairments_node(spec.to_streamer);
  out["to_player"] = impairments_node(spec.to_player);
  if (!spec.monitor && spec.client.misbehave.any()) {
    YAML::Node misbehave;
    misbehave_fields(misbehave, spec.client.misbehave);
    out["misbehave"] = misbehave;
  }
  return out;
}

YAML::Node world_node(const Scenario& scenario) {
  const WorldConfig& world = scenario.world;
  YAML::Node out;
  out["fleet"] = world.player.fleet;
  YAML::Node player;
  player["frame_rate_hz"] = shortest_number(world.player.frame_rate_hz);
  player["no_feedback_timeout"] = duration_text(world.player.no_feedback_timeout);
  player["ping_period"] = duration_text(world.player.ping_period);
  out["player"] = player;
  out["gamepad"] = gamepad_node(scenario.gamepad);
  out["vehicle_pipe_delay"] = duration_text(world.vehicle_pipe_delay);
  out["reconnect_backoff"] = duration_text(world.reconnect_backoff);
  for (const VehicleSpec& spec : world.vehicles) out["vehicles"].push_back(vehicle_node(spec));
  if (scenario.operator_client.connect) {
    // Only when connected: a world without one reads the same without the section.
    YAML::Node client;
    client["connect"] = true;
    client["keep_alive_period"] = duration_text(scenario.operator_client.keep_alive_period);
    client["reconnect_backoff"] = duration_text(scenario.operator_client.reconnect_backoff);
    out["operator_client"] = client;
  }
  return out;
}

// user data: the JSON value itself, which YAML reads back as the same value.
YAML::Node json_node(const std::string& json) { return YAML::Load(json); }

struct ActionWriter {
  YAML::Node& item;

  void operator()(const SetImpairments& set) {
    YAML::Node impair;
    impair["vehicle"] = set.vehicle;
    impair["direction"] = std::string(direction_name(set.direction));
    patch_fields(impair, set.patch);
    item["impair"] = impair;
    if (set.ramp > Micros{0}) item["ramp"] = duration_text(set.ramp);
  }
  void operator()(const LinkOutage& outage) {
    YAML::Node node;
    node["vehicle"] = outage.vehicle;
    node["direction"] = std::string(direction_name(outage.direction));
    node["for"] = duration_text(outage.duration);
    item["outage"] = node;
  }
  void operator()(const CameraStall& stall) {
    YAML::Node node;
    node["vehicle"] = stall.vehicle;
    node["camera"] = stall.camera;
    if (stall.stalled && stall.duration > Micros{0}) node["for"] = duration_text(stall.duration);
    item[stall.stalled ? "camera_stall" : "camera_unstall"] = node;
  }
  void operator()(const FrameLoopStall& stall) {
    YAML::Node node;
    node["vehicle"] = stall.vehicle;
    node["for"] = duration_text(stall.duration);
    item["frame_loop_stall"] = node;
  }
  void operator()(const ControlThreadStall& stall) {
    YAML::Node node;
    node["vehicle"] = stall.vehicle;
    node["for"] = duration_text(stall.duration);
    item["control_thread_stall"] = node;
  }
  void operator()(const DisconnectVehicle& disconnect) {
    YAML::Node node;
    node["vehicle"] = disconnect.vehicle;
    if (disconnect.listener_down > Micros{0}) node["listener_down"] = duration_text(disconnect.listener_down);
    item["disconnect"] = node;
  }
  void operator()(const SetMisbehaviour& set) {
    YAML::Node node;
    node["vehicle"] = set.vehicle;
    misbehave_fields(node, set.misbehave);
    if (set.second_connection) node["second_connection"] = true;
    item["misbehave"] = node;
  }
  void operator()(const SetOperatorMisbehaviour& set) {
    YAML::Node node;
    node["silent"] = set.misbehave.silent;
    node["malformed_json"] = set.misbehave.malformed_json;
    node["oversized_frames"] = set.misbehave.oversized_frames;
    node["bad_message"] = std::string(bad_client_message_name(set.misbehave.bad_message));
    if (set.second_connection) node["second_connection"] = true;
    item["operator_misbehave"] = node;
  }
  void operator()(const GamepadAction& pad) {
    switch (pad.kind) {
      case GamepadAction::Kind::unplug: item["gamepad"] = "unplug"; return;
      case GamepadAction::Kind::replug: item["gamepad"] = "replug"; return;
      case GamepadAction::Kind::script: item["gamepad"] = gamepad_node(pad.script); return;
    }
  }
  void operator()(const SelectVehicle& select) { item["select_vehicle"] = select.vehicle.value_or("none"); }
  void operator()(const ClientDataAction& data) {
    YAML::Node node;
    node["source"] = std::string(client_source_name(data.source));
    if (data.active_vehicle) node["active_vehicle"] = *data.active_vehicle;
    for (const auto& [vehicle, entry] : data.vehicles) {
      YAML::Node out(YAML::NodeType::Map);
      if (entry.user_data_json) out["user_data"] = json_node(*entry.user_data_json);
      if (entry.disable_gamepad) out["disable_gamepad"] = *entry.disable_gamepad;
      if (entry.echo == ClientDataAction::Echo::latest) out["echo"] = "latest";
      if (entry.echo == ClientDataAction::Echo::corrupt) out["echo"] = "corrupt";
      node["vehicles"][vehicle] = out;
    }
    if (data.every > Micros{0}) node["every"] = duration_text(data.every);
    if (data.until) node["until"] = duration_text(*data.until);
    item["client_data"] = node;
  }
};

std::string controller_state_name(DeliveryExpectation::ControllerState state) {
  switch (state) {
    case DeliveryExpectation::ControllerState::any: return "any";
    case DeliveryExpectation::ControllerState::null: return "null";
    case DeliveryExpectation::ControllerState::default_: return "default";
    case DeliveryExpectation::ControllerState::driving: return "driving";
    case DeliveryExpectation::ControllerState::safe: return "safe";
  }
  return "any";
}

struct ExpectationWriter {
  YAML::Node& expect;

  void operator()(const FaultEdgeExpectation& e) {
    YAML::Node node;
    node["fault"] = std::string(fault_identifier(e.fault));
    node["vehicle"] = e.vehicle;
    YAML::Node edge;
    edge["after"] = e.after_label.empty() ? duration_text(e.after) : e.after_label;
    if (e.min > Micros{0}) {
      edge["within"].push_back(duration_text(e.min));
      edge["within"].push_back(duration_text(e.max));
    } else {
      edge["within"] = duration_text(e.max);
    }
    node[e.raised ? "raised" : "cleared"] = edge;
    expect["faults"].push_back(node);
  }
  void operator()(const FaultNeverExpectation& e) {
    YAML::Node node;
    node["fault"] = std::string(fault_identifier(e.fault));
    if (e.vehicle) node["vehicle"] = *e.vehicle;
    node["never"] = true;
    if (e.from > Micros{0}) node["from"] = duration_text(e.from);
    if (e.until) node["until"] = duration_text(*e.until);
    expect["faults"].push_back(node);
  }
  // Times, not event names: a shrunk scenario may have lost the event a label named.
  void operator()(const FaultAlwaysExpectation& e) {
    YAML::Node node;
    node["fault"] = std::string(fault_identifier(e.fault));
    node["vehicle"] = e.vehicle;
    node["always"] = true;
    node["from"] = duration_text(e.from);
    node["until"] = e.until ? duration_text(*e.until) : "end";
    expect["faults"].push_back(node);
  }
  void operator()(const RefusesToStartExpectation& e) { expect["refuses_to_start"] = e.reason; }
  void operator()(const EventExpectation& e) {
    YAML::Node node;
    node["event"] = std::string(notable_kind_name(e.kind));
    if (e.wire == Wire::operator_) node["wire"] = "operator";
    if (e.vehicle) node["vehicle"] = *e.vehicle;
    if (e.locked) node["locked"] = std::string(client_source_name(*e.locked));
    if (e.source) node["source"] = std::string(client_source_name(*e.source));
    if (!e.reason.empty()) node["reason"] = e.reason;
    if (e.never) {
      node["never"] = true;
      if (e.from > Micros{0}) node["from"] = duration_text(e.from);
      if (e.until) node["until"] = duration_text(*e.until);
    } else {
      node["after"] = duration_text(e.from);
      if (e.min > Micros{0}) {
        node["within"].push_back(duration_text(e.min));
        node["within"].push_back(duration_text(*e.until - e.from));
      } else {
        node["within"] = duration_text(*e.until - e.from);
      }
    }
    expect["events"].push_back(node);
  }
  // Times, not event names (as for always).
  void operator()(const FeedbackExpectation& e) {
    YAML::Node node;
    node["vehicle"] = e.vehicle;
    for (const FeedbackCheck& check : e.checks) {
      if (check.as_set) {
        node[check.field] = YAML::Node(YAML::NodeType::Sequence);
        for (const auto& fault : YAML::Load(check.expected_json)) node[check.field].push_back(fault.as<std::string>());
      } else {
        node["field"] = check.field;
        node["equals"] = json_node(check.expected_json);
      }
    }
    if (e.instant) {
      node["at"] = duration_text(e.from);
    } else {
      node["from"] = duration_text(e.from);
      if (e.until) node["until"] = duration_text(*e.until);
    }
    expect["feedback"].push_back(node);
  }
  void operator()(const FaultStateExpectation& e) {
    YAML::Node node;
    node["fault"] = std::string(fault_identifier(e.fault));
    node["at"] = duration_text(e.at);
    if (e.every_vehicle_but_active) {
      node["active_on"] = "every_vehicle_but_active";
    } else {
      for (const auto& name : e.active_on) node["active_on"].push_back(name);
    }
    for (const auto& name : e.inactive_on) node["inactive_on"].push_back(name);
    expect["faults"].push_back(node);
  }
  void operator()(const ThresholdExpectation& e) {
    const std::string key = e.metric + (e.vehicle ? "{" + *e.vehicle + "}" : "");
    expect["thresholds"][key].push_back(e.text);
  }
  void operator()(const InvariantExpectation& e) {
    expect["invariants"].push_back(std::string(invariant_name(e.invariant)));
  }
  void operator()(const DeliveryExpectation& e) {
    YAML::Node node;
    node["vehicle"] = e.vehicle;
    node["after"] = e.after_label.empty() ? duration_text(e.after) : e.after_label;
    node["within"] = duration_text(e.within);
    if (e.every) node["every"] = true;
    const bool something_else = e.user_data_json || e.user_data_absent || !e.fields.empty();
    if (e.controller != DeliveryExpectation::ControllerState::any || !something_else) {
      node["controller"] = controller_state_name(e.controller);
    }
    if (!e.fields.empty()) {
      std::string fields;
      for (const ControllerFieldValue& field : e.fields) {
        fields += (fields.empty() ? "" : " ") + field.name + "=" + shortest_number(field.value);
      }
      node["fields"] = fields;
    }
    if (e.user_data_json) node["user_data"] = json_node(*e.user_data_json);
    if (e.user_data_absent) node["no_user_data"] = true;
    expect["delivered"].push_back(node);
  }
};

}  // namespace

std::string write_scenario_yaml(const Scenario& scenario, const std::string& header) {
  YAML::Node root;
  if (!scenario.description.empty()) root["description"] = scenario.description;
  root["seed"] = scenario.seed;
  root["duration"] = duration_text(scenario.duration);
  root["world"] = world_node(scenario);
  for (const TimelineEvent& event : scenario.timeline) {
    YAML::Node item;
    item["at"] = duration_text(event.at);
    if (!event.name.empty()) item["name"] = event.name;
    std::visit(ActionWriter{item}, event.action);
    root["timeline"].push_back(item);
  }
  YAML::Node expect(YAML::NodeType::Map);
  for (const Expectation& expectation : scenario.expectations) std::visit(ExpectationWriter{expect}, expectation.kind);
  root["expect"] = expect;

  std::ostringstream out;
  std::istringstream lines(header);
  for (std::string line; std::getline(lines, line);) out << "# " << line << "\n";
  YAML::Emitter emitter;
  emitter << root;
  out << emitter.c_str() << "\n";
  return out.str();
}

}  // namespace ocp::scenario
