#include "world/trace.hpp"

#include <fmt/format.h>

#include <map>
#include <utility>

#include "world/world.hpp"

namespace ocp {
namespace {

constexpr std::uint64_t fnv_offset = 0xcbf29ce484222325ull;
constexpr std::uint64_t fnv_prime = 0x100000001b3ull;

std::string_view controller_summary(const std::optional<Controller>& controller) {
  if (!controller) return "null";
  return controller->is_safe_default() ? "default" : "operator";
}

std::string join(const std::vector<std::string>& items) {
  std::string joined;
  for (const auto& item : items) {
    if (!joined.empty()) joined += ',';
    joined += item;
  }
  return joined;
}

}  // namespace

class TraceRecorder::StreamerWatcher final : public StreamerObserver {
 public:
  StreamerWatcher(TraceRecorder& recorder, std::string component)
      : recorder_(recorder), component_(std::move(component)) {}

  void on_fault_changed(FaultId fault, bool active) override {
    recorder_.record(component_, fmt::format("fault {} {}", fault_identifier(fault),
                                             active ? "raised" : "cleared"));
  }
  void on_vehicle_connection(bool connected, const std::string& peer) override {
    recorder_.record(component_, fmt::format("vehicle {} {}", connected ? "connected" : "disconnected", peer));
  }
  void on_control_sent(const OcpControlMessage& message) override {
    if (!recorder_.options_.messages) return;
    recorder_.record(component_,
                     fmt::format("control ack={} mac={} latency={} fault={} controller={}{}",
                                 message.ack.ack_time, message.ack.ack_time_mac,
                                 message.telemetry.latency_ms, message.telemetry.fault,
                                 controller_summary(message.controller),
                                 message.client_user_data ? " user_data" : ""));
  }
  void on_vehicle_response(const VehicleResponseMessage& message) override {
    if (!recorder_.options_.messages) return;
    recorder_.record(component_, fmt::format("response ack={} mac={}", message.ack.ack_time,
                                             message.ack.ack_time_mac));
  }

 private:
  TraceRecorder& recorder_;
  std::string component_;
};

// Reads the Player's VehicleOcpShared every frame and records what changed per vehicle.
class TraceRecorder::PlayerWatcher {
 public:
  PlayerWatcher(TraceRecorder& recorder, std::string component)
      : recorder_(recorder), component_(std::move(component)) {}

  void on_shared(const VehicleOcpShared& shared) {
    for (const auto& [vehicle, feedback] : shared.vehicle_feedback) {
      Seen& seen = seen_[vehicle];
      if (!seen.initialised || seen.sender_fault != feedback.sender_fault) {
        recorder_.record(component_, fmt::format("{} sender_fault [{}]", vehicle, join(feedback.sender_fault)));
        seen.sender_fault = feedback.sender_fault;
      }
      if (!seen.initialised || seen.receiver_fault != feedback.receiver_fault) {
        recorder_.record(component_, fmt::format("{} receiver_fault [{}]", vehicle, join(feedback.receiver_fault)));
        seen.receiver_fault = feedback.receiver_fault;
      }
      if (!seen.initialised || seen.missing_cameras != feedback.missing_cameras) {
        if (feedback.missing_cameras) {
          recorder_.record(component_, fmt::format("{} missing_cameras [{}]", vehicle,
                                                   join(*feedback.missing_cameras)));
        } else {
          recorder_.record(component_, fmt::format("{} missing_cameras null", vehicle));
        }
        seen.missing_cameras = feedback.missing_cameras;
      }
      if (recorder_.options_.messages && seen.latency != feedback.message_latency_roundtrip) {
        if (feedback.message_latency_roundtrip) {
          recorder_.record(component_, fmt::format("{} latency {}", vehicle,
                                                   *feedback.message_latency_roundtrip));
        } else {
          recorder_.record(component_, fmt::format("{} latency null", vehicle));
        }
        seen.latency = feedback.message_latency_roundtrip;
      }
      seen.initialised = true;
    }
  }

 private:
  struct Seen {
    bool initialised = false;
    std::vector<std::string> sender_fault;
    std::vector<std::string> receiver_fault;
    std::optional<std::vector<std::string>> missing_cameras;
    std::optional<std::uint64_t> latency;
  };
  TraceRecorder& recorder_;
  std::string component_;
  std::map<std::string, Seen> seen_;
};

TraceRecorder::TraceRecorder(const Executor& executor, TraceOptions options)
    : executor_(executor), options_(options), digest_(fnv_offset) {}

TraceRecorder::~TraceRecorder() = default;

LogSink TraceRecorder::sink() {
  return [this](const LogRecord& record) {
    if (record.level < options_.minimum_log_level) return;
    line_.clear();
    fmt::format_to(std::back_inserter(line_), "{:>12} {} {}: {}\n", record.time.count(),
                   record.component, log_level_name(record.level), record.message);
    append_line();
  };
}

void TraceRecorder::observe(World& world) {
  if (!world.running()) {
    world.set_on_built([this](World& built) { install(built); });
    return;
  }
  install(world);
}

void TraceRecorder::install(World& world) {
  for (const std::string& vehicle : world.vehicles()) {
    auto watcher = std::make_unique<StreamerWatcher>(*this, "streamer:" + vehicle);
    world.streamer(vehicle).set_observer(watcher.get());
    streamer_watchers_.push_back(std::move(watcher));
  }
  player_watcher_ = std::make_unique<PlayerWatcher>(*this, world.player().config().name);
  PlayerWatcher* watcher = player_watcher_.get();
  world.player().add_shared_listener([watcher](const VehicleOcpShared& shared) { watcher->on_shared(shared); });
}

void TraceRecorder::record(std::string_view component, std::string_view event) {
  line_.clear();
  fmt::format_to(std::back_inserter(line_), "{:>12} {} {}\n", executor_.now().count(), component, event);
  append_line();
}

void TraceRecorder::append_line() {
  for (const char character : line_) {
    digest_ = (digest_ ^ static_cast<unsigned char>(character)) * fnv_prime;
  }
  ++lines_;
  if (options_.keep_text) text_ += line_;
}

std::vector<std::string> TraceRecorder::lines_containing(std::string_view needle) const {
  std::vector<std::string> found;
  std::size_t start = 0;
  while (start < text_.size()) {
    std::size_t end = text_.find('\n', start);
    if (end == std::string::npos) end = text_.size();
    const std::string_view line(text_.data() + start, end - start);
    if (line.find(needle) != std::string_view::npos) found.emplace_back(line);
    start = end + 1;
  }
  return found;
}

}  // namespace ocp
