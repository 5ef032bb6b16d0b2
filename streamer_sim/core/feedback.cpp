// The frame loop's output (SPEC §4.1 source data, §6 StreamerSlow, §8): one StreamerFeedback
// per iteration, and each camera's video frames carrying the latest echoed pair as SEI.
#include "streamer_impl.hpp"

namespace ocp {

void StreamerCore::Impl::on_frame_iteration(Micros took) {
  ++stats.frame_loop_iterations;
  // Raised by the iteration that overran; cleared by the next iteration that did not.
  faults.set(FaultId::StreamerSlow, took > config.streamer_slow_threshold);
  send_feedback();
}

void StreamerCore::Impl::send_feedback() {
  const SimTime now = executor.now();
  StreamerFeedback feedback;
  feedback.sequence = feedback_sequence++;
  feedback.receiver_faults = faults.faults().to_vector();
  feedback.latency_ms = latency_loop.latency_ms(now);
  feedback.missing_cameras = missing_cameras;
  if (vehicle_data) {
    feedback.vehicle_data = vehicle_data;
    feedback.vehicle_data_age = now - vehicle_data_arrived_at;
  }
  feedback.last_remote_input = last_sent_controller;
  ++stats.feedback_sent;
  send_to_player(std::move(feedback));
}

void StreamerCore::Impl::send_video_frame(VideoFrame&& frame) {
  frame.sei = echoed_pair;
  ++stats.video_frames_sent;
  send_to_player(std::move(frame));
}

void StreamerCore::Impl::send_to_player(LinkMessage&& message) {
  if (to_player != nullptr) to_player->send(std::move(message));
}

}  // namespace ocp
