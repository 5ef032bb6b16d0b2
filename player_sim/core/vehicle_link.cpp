// Per-vehicle inputs from the Streamer and the operator-side fault rules (SPEC §6).
#include "vehicle_link.hpp"

#include <utility>

namespace ocp {

void VehicleLink::on_feedback(StreamerFeedback&& feedback, SimTime now) {
  last_feedback = std::move(feedback);
  feedback_arrived_at = now;
}

void VehicleLink::on_video_frame(const VideoFrame& frame) {
  // Every frame carrying SEI updates the pair; frames without one leave it as it was.
  if (frame.sei) latest_sei = *frame.sei;
}

void VehicleLink::on_pong(const Pong& pong, SimTime now) {
  // Duplicated or reordered pongs of older pings must not overwrite a newer measurement.
  if (newest_pong_id && pong.id <= *newest_pong_id) return;
  newest_pong_id = pong.id;
  const Micros round_trip = now - pong.ping_sent_at;
  ping_latency_ms = round_trip.count() > 0 ? static_cast<std::uint64_t>(to_whole_ms(round_trip)) : 0;
}

FaultSet evaluate_sender_faults(const VehicleLink& link, const SenderFaultInputs& inputs) {
  FaultSet faults;
  const SimTime feedback_reference =
      link.last_feedback ? link.feedback_arrived_at : inputs.measured_since;
  faults.set(FaultId::NoFeedbackMessage,
             inputs.now - feedback_reference > inputs.no_feedback_timeout);
  if (link.monitor) return faults;
  faults.set(FaultId::InputLost, !inputs.gamepad_plugged && !link.client.disable_gamepad);
  faults.set(FaultId::VehicleControlInactive, !inputs.is_active);
  return faults;
}

}  // namespace ocp
