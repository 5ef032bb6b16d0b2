#include "loop_recorder.hpp"

#include <variant>

namespace ocp::bench {

LoopRecorder::LoopRecorder(EventBus& events, SimTime start)
    : start_(start), subscription_(events.subscribe([this](const Event& event) { on_event(event); })) {}

double LoopRecorder::seconds(SimTime at) const {
  return static_cast<double>((at - start_).count()) / 1e6;
}

void LoopRecorder::on_event(const Event& event) {
  if (const auto* frame = std::get_if<WireFrame>(&event.body)) {
    if (frame->wire == Wire::vehicle) on_frame(*frame, event.time);
  } else if (const auto* sample = std::get_if<LatencySample>(&event.body)) {
    if (!connected_once()) return;
    tick_lateness_us_.push_back(static_cast<double>(sample->tick_lateness.count()));
    if (sample->latency_ms) {
      latency_ms_.push_back(static_cast<double>(*sample->latency_ms));
      latency_series_ms_.push_back({seconds(event.time), static_cast<double>(*sample->latency_ms)});
    }
  } else if (const auto* fault = std::get_if<FaultEvent>(&event.body)) {
    faults_.push_back({seconds(event.time), std::string(fault_identifier(fault->id)), fault->active,
                       !connected_once()});
  } else if (const auto* connection = std::get_if<ConnectionEvent>(&event.body)) {
    if (connection->wire == Wire::vehicle && connection->change == ConnectionChange::opened) {
      if (connections_ == 0) first_connect_s_ = seconds(event.time);
      ++connections_;
    }
  }
}

void LoopRecorder::on_frame(const WireFrame& frame, SimTime at) {
  if (!frame.ack) return;
  if (frame.direction == FrameDirection::out) {
    ++control_frames_;
    sent_at_.emplace_back(frame.ack->ack_time, at);
    if (sent_at_.size() > 4096) sent_at_.pop_front();   // a client that stopped answering
    return;
  }
  response_times_s_.push_back(seconds(at));
  // Older pairs the client skipped (one answering on its own timer echoes only the newest)
  // will never come back; a pair not pending any more is a repeat of one already counted.
  const std::uint64_t ack_time = frame.ack->ack_time;
  while (!sent_at_.empty() && sent_at_.front().first < ack_time) sent_at_.pop_front();
  if (sent_at_.empty() || sent_at_.front().first != ack_time) return;
  const auto delay_us = static_cast<double>((at - sent_at_.front().second).count());
  sent_at_.pop_front();
  echo_delays_us_.push_back(delay_us);
  echo_series_us_.push_back({seconds(at), delay_us});
}

}  // namespace ocp::bench
