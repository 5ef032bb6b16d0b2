#include "fleet_recorder.hpp"

#include <variant>

namespace ocp::bench {

FleetRecorder::FleetRecorder(EventBus& events, const std::vector<std::string>& vehicles) : pending_(vehicles.size()) {
  for (std::size_t index = 0; index < vehicles.size(); ++index) index_.emplace(vehicles[index], index);
  subscriptions_.push_back(events.subscribe([this](const Event& event) { on_event(event, unknown_vehicle); }));
}

FleetRecorder::FleetRecorder(const std::vector<EventBus*>& buses) : pending_(buses.size()) {
  for (std::size_t index = 0; index < buses.size(); ++index) {
    subscriptions_.push_back(buses[index]->subscribe([this, index](const Event& event) { on_event(event, index); }));
  }
}

void FleetRecorder::merge(const FleetRecorder& other) {
  tick_lateness_us_.insert(tick_lateness_us_.end(), other.tick_lateness_us_.begin(), other.tick_lateness_us_.end());
  echo_delays_us_.insert(echo_delays_us_.end(), other.echo_delays_us_.begin(), other.echo_delays_us_.end());
  for (std::size_t id = 0; id < fault_count; ++id) faults_raised_[id] += other.faults_raised_[id];
  connections_ += other.connections_;
  responses_ += other.responses_;
  control_frames_ += other.control_frames_;
  control_bytes_ += other.control_bytes_;
  response_bytes_ += other.response_bytes_;
  if (sample_control_.empty()) sample_control_ = other.sample_control_;
  if (sample_response_.empty()) sample_response_ = other.sample_response_;
}

void FleetRecorder::on_event(const Event& event, std::size_t vehicle) {
  if (event.component.kind != ComponentKind::streamer) return;
  const bool recording = recording_.load(std::memory_order_relaxed);
  if (const auto* frame = std::get_if<WireFrame>(&event.body)) {
    if (frame->wire != Wire::vehicle || !frame->ack) return;
    if (vehicle == unknown_vehicle) {
      const auto found = index_.find(event.component.name);
      if (found == index_.end()) return;
      vehicle = found->second;
    }
    on_frame(vehicle, *frame, event.time);
  } else if (const auto* sample = std::get_if<LatencySample>(&event.body)) {
    if (recording) tick_lateness_us_.push_back(static_cast<double>(sample->tick_lateness.count()));
  } else if (const auto* fault = std::get_if<FaultEvent>(&event.body)) {
    const auto id = static_cast<std::size_t>(fault->id);
    if (recording && fault->active && id < fault_count) ++faults_raised_[id];
  } else if (const auto* connection = std::get_if<ConnectionEvent>(&event.body)) {
    if (connection->wire == Wire::vehicle && connection->change == ConnectionChange::opened) {
      connections_.fetch_add(1, std::memory_order_relaxed);
    }
  }
}

void FleetRecorder::on_frame(std::size_t vehicle, const WireFrame& frame, SimTime at) {
  auto& pending = pending_[vehicle];
  const bool recording = recording_.load(std::memory_order_relaxed);
  const std::uint64_t wire_bytes = sizeof frame.length_prefix + frame.payload.size();
  if (frame.direction == FrameDirection::out) {
    if (recording) {
      ++control_frames_;
      control_bytes_ += wire_bytes;
      if (sample_control_.empty()) sample_control_ = frame.payload;
    }
    pending.emplace_back(frame.ack->ack_time, at);
    if (pending.size() > 256) pending.pop_front();   // a vehicle that stopped answering
    return;
  }
  if (recording) {
    ++responses_;
    response_bytes_ += wire_bytes;
    if (sample_response_.empty()) sample_response_ = frame.payload;
  }
  const std::uint64_t ack_time = frame.ack->ack_time;
  while (!pending.empty() && pending.front().first < ack_time) pending.pop_front();
  if (pending.empty() || pending.front().first != ack_time) return;
  if (recording) echo_delays_us_.push_back(static_cast<double>((at - pending.front().second).count()));
  pending.pop_front();
}

}  // namespace ocp::bench
