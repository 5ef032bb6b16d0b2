#include "fleet_recorder.hpp"

#include <variant>

namespace ocp::bench {

FleetRecorder::FleetRecorder(EventBus& events, const std::vector<std::string>& vehicles)
    : pending_(vehicles.size()), subscription_(events.subscribe([this](const Event& event) { on_event(event); })) {
  for (std::size_t index = 0; index < vehicles.size(); ++index) index_.emplace(vehicles[index], index);
}

void FleetRecorder::on_event(const Event& event) {
  if (event.component.kind != ComponentKind::streamer) return;
  if (const auto* frame = std::get_if<WireFrame>(&event.body)) {
    if (frame->wire != Wire::vehicle || !frame->ack) return;
    const auto found = index_.find(event.component.name);
    if (found != index_.end()) on_frame(found->second, *frame, event.time);
  } else if (const auto* sample = std::get_if<LatencySample>(&event.body)) {
    if (recording_) tick_lateness_us_.push_back(static_cast<double>(sample->tick_lateness.count()));
  } else if (const auto* fault = std::get_if<FaultEvent>(&event.body)) {
    const auto id = static_cast<std::size_t>(fault->id);
    if (recording_ && fault->active && id < fault_count) ++faults_raised_[id];
  } else if (const auto* connection = std::get_if<ConnectionEvent>(&event.body)) {
    if (connection->wire == Wire::vehicle && connection->change == ConnectionChange::opened) ++connections_;
  }
}

void FleetRecorder::on_frame(std::size_t vehicle, const WireFrame& frame, SimTime at) {
  auto& pending = pending_[vehicle];
  if (frame.direction == FrameDirection::out) {
    pending.emplace_back(frame.ack->ack_time, at);
    if (pending.size() > 256) pending.pop_front();   // a vehicle that stopped answering
    return;
  }
  if (recording_) ++responses_;
  const std::uint64_t ack_time = frame.ack->ack_time;
  while (!pending.empty() && pending.front().first < ack_time) pending.pop_front();
  if (pending.empty() || pending.front().first != ack_time) return;
  if (recording_) echo_delays_us_.push_back(static_cast<double>((at - pending.front().second).count()));
  pending.pop_front();
}

}  // namespace ocp::bench
