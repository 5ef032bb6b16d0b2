// Per-vehicle inputs from the Streamer (PlayerCore::handle_link_message routes each to its
// vehicle) and the operator-side fault rules (SPEC §6).
#include "vehicle_link.hpp"

#include <utility>
#include <variant>

#include "ocp/invariant.hpp"
#include "player_impl.hpp"

namespace ocp {

void VehicleLink::on_feedback(StreamerFeedback&& feedback, SimTime now) {
  const SimTime arrived_before = feedback_arrived_at;
  last_feedback = std::move(feedback);
  feedback_arrived_at = now;
  OCP_INVARIANT(feedback_arrived_at >= arrived_before, "feedback arrival times never go back");
}

void VehicleLink::on_video_frame(const VideoFrame& frame) {
  // Every frame carrying SEI updates the pair; frames without one leave it as it was.
  if (frame.sei) latest_sei = *frame.sei;
  OCP_INVARIANT(!frame.sei || latest_sei == frame.sei, "the latest SEI pair is the one this frame carried");
}

void VehicleLink::on_pong(const Pong& pong, SimTime now) {
  // Duplicated or reordered pongs of older pings must not overwrite a newer measurement.
  if (newest_pong_id && pong.id <= *newest_pong_id) return;
  newest_pong_id = pong.id;
  const Micros round_trip = now - pong.ping_sent_at;
  ping_latency_ms = round_trip.count() > 0 ? static_cast<std::uint64_t>(to_whole_ms(round_trip)) : 0;
  OCP_INVARIANT(newest_pong_id && *newest_pong_id == pong.id, "the newest pong id only moves forward, to this pong");
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
  // Fault sets consistent with their conditions' inputs.
  OCP_INVARIANT(faults.contains(FaultId::InputLost) == (!inputs.gamepad_plugged && !link.client.disable_gamepad),
                "InputLost is raised exactly when the gamepad is unplugged and in use");
  OCP_INVARIANT(faults.contains(FaultId::VehicleControlInactive) != inputs.is_active,
                "VehicleControlInactive is raised exactly when the vehicle is not the active one");
  OCP_INVARIANT(faults.contains(FaultId::NoFeedbackMessage) ==
                    (inputs.now - feedback_reference > inputs.no_feedback_timeout),
                "NoFeedbackMessage is raised exactly when feedback is older than the timeout");
  return faults;
}

void PlayerCore::handle_link_message(const std::string& vehicle, LinkMessage&& message) {
  Impl& self = *impl_;
  const auto found = self.vehicles.find(vehicle);
  if (found == self.vehicles.end()) {
    if (self.warned_unknown_senders.first_time(vehicle, self.executor.now())) {
      self.logger.warn("message from unknown vehicle '{}' dropped", vehicle);
    }
    return;
  }
  VehicleLink& link = found->second;
  const SimTime now = self.executor.now();
  if (auto* feedback = std::get_if<StreamerFeedback>(&message)) {
    ++self.stats.feedback_received;
    link.on_feedback(std::move(*feedback), now);
  } else if (auto* frame = std::get_if<VideoFrame>(&message)) {
    ++self.stats.video_frames_received;
    link.on_video_frame(*frame);
  } else if (auto* pong = std::get_if<Pong>(&message)) {
    ++self.stats.pongs_received;
    link.on_pong(*pong, now);
  } else {
    self.logger.warn("unexpected Player-bound message kind {} from '{}' dropped", message.index(), vehicle);
  }
}

}  // namespace ocp
