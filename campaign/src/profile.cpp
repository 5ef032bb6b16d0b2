// Profile files (profile.hpp): YAML → Profile, every key and range checked with its position.
#include "campaign/profile.hpp"
#include "ocp/bounded_file.hpp"

#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "scenario/parse.hpp"
#include "scenario/write.hpp"
#include "sim_app/data_dir.hpp"
#include "world/seeds.hpp"

namespace ocp::campaign {

std::string_view action_kind_name(ActionKind kind) {
  switch (kind) {
    case ActionKind::impair: return "impair";
    case ActionKind::latency_ramp: return "latency_ramp";
    case ActionKind::outage: return "outage";
    case ActionKind::burst_loss: return "burst_loss";
    case ActionKind::camera_stall: return "camera_stall";
    case ActionKind::frame_loop_stall: return "frame_loop_stall";
    case ActionKind::control_thread_stall: return "control_thread_stall";
    case ActionKind::disconnect: return "disconnect";
    case ActionKind::misbehave: return "misbehave";
    case ActionKind::gamepad_unplug: return "gamepad_unplug";
    case ActionKind::client_data: return "client_data";
    case ActionKind::select_vehicle: return "select_vehicle";
    case ActionKind::operator_misbehave: return "operator_misbehave";
  }
  return "?";
}

// The shipped profiles are data (sim_app/data_dir.hpp): share/ocp-sim/campaign/profiles.
std::string shipped_profile_path(const std::string& name) {
  try {
    return (sim_app::find_data("campaign/profiles") / (name + ".yaml")).string();
  } catch (const sim_app::DataNotFound& missing) {
    throw ProfileError(std::string("profile '") + name + "': " + missing.what());
  }
}

namespace {

// Upper bounds that keep one world small whatever a profile says ("limits on everything").
constexpr Micros max_duration{3'600'000'000};
constexpr Micros max_timer{60'000'000};
constexpr int max_vehicles = 16;
constexpr int max_cameras = 8;
constexpr int max_events = 200;

class Reader {
 public:
  explicit Reader(std::string path) : path_(std::move(path)) {}

  [[noreturn]] void fail(const YAML::Node& node, const std::string& reason) const {
    const YAML::Mark mark = node.Mark();
    throw ProfileError(path_ + ":" + std::to_string(mark.line + 1) + ":" + std::to_string(mark.column + 1) + ": " +
                       reason);
  }
  void check_keys(const YAML::Node& node, const std::string& what, const std::vector<std::string>& allowed) const {
    if (!node.IsMap()) fail(node, what + ": expected a mapping");
    for (const auto& item : node) {
      const std::string key = item.first.as<std::string>();
      if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
        std::string known;
        for (const auto& name : allowed) known += (known.empty() ? "" : ", ") + name;
        fail(item.first, "unknown key '" + key + "' in " + what + " (known: " + known + ")");
      }
    }
  }
  Micros duration(const YAML::Node& node) const {
    if (!node.IsScalar()) fail(node, "expected a duration like 350ms");
    try {
      return scenario::parse_duration_text(node.Scalar());
    } catch (const std::invalid_argument& error) {
      fail(node, error.what());
    }
  }
  double number(const YAML::Node& node) const {
    if (!node.IsScalar()) fail(node, "expected a number");
    char* end = nullptr;
    const double value = std::strtod(node.Scalar().c_str(), &end);
    if (node.Scalar().empty() || *end != '\0' || !std::isfinite(value)) fail(node, "expected a number, got '" + node.Scalar() + "'");
    return value;
  }
  const YAML::Node& pair(const YAML::Node& node) const {
    if (!node.IsSequence() || node.size() != 2) fail(node, "expected [min, max]");
    return node;
  }
  void durations(const YAML::Node& node, DurationRange& out, Micros low, Micros high) const {
    pair(node);
    out = {duration(node[0]), duration(node[1])};
    if (out.min > out.max) fail(node, "min > max");
    if (out.min < low || out.max > high) {
      fail(node, "out of range [" + scenario::duration_text(low) + ", " + scenario::duration_text(high) + "]");
    }
  }
  void numbers(const YAML::Node& node, NumberRange& out, double low, double high) const {
    pair(node);
    out = {number(node[0]), number(node[1])};
    if (out.min > out.max) fail(node, "min > max");
    if (out.min < low || out.max > high) {
      std::ostringstream text;
      text << "out of range [" << low << ", " << high << "]";
      fail(node, text.str());
    }
  }
  void integers(const YAML::Node& node, int& min, int& max, int low, int high) const {
    NumberRange range;
    numbers(node, range, low, high);
    if (range.min != std::floor(range.min) || range.max != std::floor(range.max)) fail(node, "expected whole numbers");
    min = static_cast<int>(range.min);
    max = static_cast<int>(range.max);
  }
  double fraction(const YAML::Node& node) const {
    const double value = number(node);
    if (value < 0 || value > 1) fail(node, "expected a number in [0, 1]");
    return value;
  }

 private:
  std::string path_;
};

// The sections of a profile file, each into its part of the Profile.
void read_timers(const Reader& read, const YAML::Node& timers, Profile& profile) {
  read.check_keys(timers, "timers", {"latency_limit", "no_control_timeout", "vehicle_read_timeout",
                                     "camera_drop_timeout", "streamer_slow_threshold", "control_queue_limit",
                                     "control_queue_max_age", "no_feedback_timeout", "reconnect_backoff",
                                     "operator_keep_alive_period"});
  const std::vector<std::pair<const char*, DurationRange*>> durations = {
      {"latency_limit", &profile.latency_limit},
      {"no_control_timeout", &profile.no_control_timeout},
      {"vehicle_read_timeout", &profile.vehicle_read_timeout},
      {"camera_drop_timeout", &profile.camera_drop_timeout},
      {"streamer_slow_threshold", &profile.streamer_slow_threshold},
      {"control_queue_max_age", &profile.control_queue_max_age},
      {"no_feedback_timeout", &profile.no_feedback_timeout},
      {"reconnect_backoff", &profile.reconnect_backoff},
      {"operator_keep_alive_period", &profile.operator_keep_alive_period}};
  // Timers shorter than a few control periods would make every world a fault storm.
  for (const auto& [key, range] : durations) {
    if (timers[key]) read.durations(timers[key], *range, Micros{30'000}, max_timer);
  }
  if (timers["control_queue_limit"]) read.numbers(timers["control_queue_limit"], profile.control_queue_limit, 2, 10'000);
}

void read_link(const Reader& read, const YAML::Node& link, Profile& profile) {
  read.check_keys(link, "link", {"delay", "jitter", "loss"});
  if (link["delay"]) read.durations(link["delay"], profile.base_delay, Micros{0}, Micros{5'000'000});
  if (link["jitter"]) read.durations(link["jitter"], profile.base_jitter, Micros{0}, Micros{1'000'000});
  if (link["loss"]) read.numbers(link["loss"], profile.base_loss, 0, 1);
}

void read_timeline(const Reader& read, const YAML::Node& timeline, Profile& profile) {
  read.check_keys(timeline, "timeline", {"events", "episode", "delay", "jitter", "loss", "duplicate", "reorder",
                                         "reorder_extra_delay", "bandwidth_bps", "queue_limit_bytes"});
  if (timeline["events"]) read.integers(timeline["events"], profile.events_min, profile.events_max, 0, max_events);
  if (timeline["episode"]) read.durations(timeline["episode"], profile.episode, Micros{10'000}, max_timer);
  if (timeline["delay"]) read.durations(timeline["delay"], profile.delay, Micros{0}, Micros{10'000'000});
  if (timeline["jitter"]) read.durations(timeline["jitter"], profile.jitter, Micros{0}, Micros{1'000'000});
  if (timeline["reorder_extra_delay"]) {
    read.durations(timeline["reorder_extra_delay"], profile.reorder_extra_delay, Micros{0}, Micros{1'000'000});
  }
  if (timeline["loss"]) read.numbers(timeline["loss"], profile.loss, 0, 1);
  if (timeline["duplicate"]) read.numbers(timeline["duplicate"], profile.duplicate, 0, 1);
  if (timeline["reorder"]) read.numbers(timeline["reorder"], profile.reorder, 0, 1);
  if (timeline["bandwidth_bps"]) read.numbers(timeline["bandwidth_bps"], profile.bandwidth_bps, 1'000, 1e10);
  if (timeline["queue_limit_bytes"]) read.numbers(timeline["queue_limit_bytes"], profile.queue_limit_bytes, 100, 1e9);
}

void read_weights(const Reader& read, const YAML::Node& weights, Profile& profile) {
  std::vector<std::string> names;
  for (int k = 0; k < action_kind_count; ++k) names.emplace_back(action_kind_name(static_cast<ActionKind>(k)));
  read.check_keys(weights, "weights", names);
  for (int k = 0; k < action_kind_count; ++k) {
    const auto kind = static_cast<ActionKind>(k);
    if (const YAML::Node weight = weights[std::string(action_kind_name(kind))]) {
      const double value = read.number(weight);
      if (value < 0 || value > 1e6) read.fail(weight, "weight out of range [0, 1000000]");
      profile.weights[kind] = value;
    }
  }
}

YAML::Node load_yaml(const std::string& text, const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::DeepRecursion& error) {
    throw ProfileError(path + ":" + std::to_string(error.mark.line + 1) + ":" + std::to_string(error.mark.column + 1) +
                       ": nested deeper than " + std::to_string(error.depth() - 1) + " levels of lists or mappings");
  } catch (const YAML::ParserException& error) {
    throw ProfileError(path + ":" + std::to_string(error.mark.line + 1) + ":" + std::to_string(error.mark.column + 1) +
                       ": " + error.msg);
  }
  if (!root || root.IsNull()) throw ProfileError(path + ":1:1: empty profile");
  return root;
}

}  // namespace

Profile parse_profile(const std::string& text, const std::string& path) {
  Profile profile;
  profile.name = std::filesystem::path(path).stem().string();
  profile.digest = derive_seed(0x0c9a3a16e5ULL, text);
  for (int k = 0; k < action_kind_count; ++k) profile.weights[static_cast<ActionKind>(k)] = 1.0;
  const Reader read(path);
  const YAML::Node root = load_yaml(text, path);
  read.check_keys(root, "profile", {"description", "duration", "vehicles", "monitor_share", "operator_client_share",
                                    "cameras", "camera_fps", "timers", "link", "timeline", "weights",
                                    "determinism_share"});
  if (root["duration"]) read.durations(root["duration"], profile.duration, Micros{1'000'000}, max_duration);
  if (root["vehicles"]) read.integers(root["vehicles"], profile.vehicles_min, profile.vehicles_max, 1, max_vehicles);
  if (root["monitor_share"]) profile.monitor_share = read.fraction(root["monitor_share"]);
  if (root["operator_client_share"]) profile.operator_client_share = read.fraction(root["operator_client_share"]);
  if (root["cameras"]) read.integers(root["cameras"], profile.cameras_min, profile.cameras_max, 1, max_cameras);
  if (root["camera_fps"]) read.numbers(root["camera_fps"], profile.camera_fps, 1, 240);
  if (root["determinism_share"]) profile.determinism_share = read.fraction(root["determinism_share"]);
  if (const YAML::Node timers = root["timers"]) read_timers(read, timers, profile);
  if (const YAML::Node link = root["link"]) read_link(read, link, profile);
  if (const YAML::Node timeline = root["timeline"]) read_timeline(read, timeline, profile);
  if (const YAML::Node weights = root["weights"]) read_weights(read, weights, profile);
  return profile;
}

Profile load_profile(const std::string& path) {
  auto text = read_bounded_file(path, file_kinds::profile);
  if (!text) throw ProfileError(text.error().detail);   // "PATH: why", the system's reason included
  return parse_profile(*text, path);
}

}  // namespace ocp::campaign
