// The control tick (SPEC §3.2, §5, §6): every control_period on absolute deadlines, evaluate
// the time-driven faults, then — while a vehicle is connected — build one OcpControlMessage
// with a fresh MAC'd ack pair and write it as one frame. Buffers are reused: no allocation on
// the steady-state path beyond what user data and camera names need.
#include "ocp/frame.hpp"
#include "ocp/invariant.hpp"
#include "ocp/json_codec.hpp"
#include "ocp/log_limiter.hpp"
#include "ocp/mutants.hpp"
#include "streamer_impl.hpp"

namespace ocp {

void StreamerCore::Impl::on_control_tick(SimTime deadline) {
  ++stats.control_ticks;
  // One instant per tick: the faults, the telemetry latency and the issued ack_time agree.
  const SimTime now = executor.now();
  evaluate_tick_faults(now);
  control_sent = false;
  if (vehicle_connection && !control_output_paused) {
    build_control_message(now);
    send_control_message();
  }
  publish_latency_sample(deadline, now);
  summarise_user_data_drops(now);
  summarise_pair_rejections(now);
  OCP_INVARIANT(stats.control_frames_sent <= stats.control_ticks, "at most one control frame a tick");
  OCP_INVARIANT(!control_sent || json_buffer.size() <= max_payload_bytes, "a control frame is never above 16 KiB");
}

// A client that alternates a good and a made-up pair (or a replay beside a live session) opens
// an InvalidMac episode every other message: each is told once, then summarised.
void StreamerCore::Impl::summarise_pair_rejections(SimTime now) {
  if (!pair_rejections.in_episode()) return;
  if (const auto summary = pair_rejections.summary(now)) {
    logger.warn("latency loop not closed (InvalidMac) again: {}{}", summary->text("more episodes"),
                summary->episode_ended ? " (none since)" : "");
  }
}

void StreamerCore::Impl::summarise_user_data_drops(SimTime now) {
  if (!user_data_drops.in_episode()) return;
  if (const auto summary = user_data_drops.summary(now)) {
    logger.warn("control message over {} bytes: sent without client_user_data {}{}", max_payload_bytes,
                summary->text("times"), summary->episode_ended ? " (none since)" : "");
  }
}

void StreamerCore::Impl::evaluate_tick_faults(SimTime now) {
  faults.set(FaultId::VehicleNoResponse, vehicle_connection == nullptr);
  // Measured from start when no operator message ever arrived.
  Micros no_control_timeout = config.no_control_timeout;
#ifdef OCP_MUTANTS
  if (mutant_active(Mutant::fault_raised_one_tick_late)) no_control_timeout += config.control_period;
#endif
  faults.set(FaultId::NoControlMessage, now - last_operator_arrival > no_control_timeout);
  // The newest valid pair ages with every tick: a loop that stops turning shows it.
  const auto latency = latency_loop.latency(now);
  faults.set(FaultId::HighLatency, latency && *latency > config.latency_limit);
  cameras.missing_cameras(now, config.camera_drop_timeout, missing_cameras);
  faults.set(FaultId::CameraLost, !missing_cameras.empty());
  evaluate_inbox_fault();
  // The fault set agrees with the inputs of its time-driven conditions.
  const FaultSet& active = faults.faults();
  OCP_INVARIANT(active.contains(FaultId::VehicleNoResponse) == (vehicle_connection == nullptr),
                "VehicleNoResponse is raised exactly when no vehicle is connected");
  OCP_INVARIANT(active.contains(FaultId::NoControlMessage) == (now - last_operator_arrival > no_control_timeout),
                "NoControlMessage is raised exactly when the operator was silent beyond the timeout");
  OCP_INVARIANT(active.contains(FaultId::HighLatency) == (latency && *latency > config.latency_limit),
                "HighLatency is raised exactly when the loop latency is above the limit");
  OCP_INVARIANT(active.contains(FaultId::CameraLost) == !missing_cameras.empty(),
                "CameraLost is raised exactly when a camera is missing");
}

void StreamerCore::Impl::build_control_message(SimTime now) {
  const FaultSet& active = faults.faults();
  if (!operator_controller) {
    outgoing.controller.reset();  // gamepad disabled: null, also during faults
  } else if (active.any_control_path()
#ifdef OCP_MUTANTS
             && !mutant_active(Mutant::default_controller_not_applied)
#endif
  ) {
    outgoing.controller = Controller::safe_default();
  } else {
    outgoing.controller = operator_controller;
  }
  outgoing.telemetry.latency_ms = latency_loop.latency_ms(now).value_or(0);
  outgoing.telemetry.fault = !active.empty();
  outgoing.telemetry.fault_reason = faults.reason();   // copied into the reused buffer
  outgoing.telemetry.missing_cameras = missing_cameras;
  outgoing.ack = latency_loop.issue(now);
  outgoing.client_user_data = operator_user_data;
  OCP_INVARIANT(!active.any_control_path() || !outgoing.controller ||
                    *outgoing.controller == Controller::safe_default() || OCP_MUTATED(default_controller_not_applied),
                "during a control-path fault the vehicle gets the default controller (or null)");
  OCP_INVARIANT(outgoing.telemetry.fault == !active.empty(), "telemetry.fault says whether any fault is active");
}

void StreamerCore::Impl::send_control_message() {
  encode_control_message(outgoing, json_buffer);
  Status sent = vehicle_connection->send(json_buffer, outgoing.ack);
  if (!sent && sent.error().code == LocalError::frame_too_large) {
    // Only oversized client user data can do this; the vehicle still needs its control. The
    // operator keeps sending that user data at 100 Hz: said once, then counted (one line a
    // period while it goes on, see summarise_user_data_drops).
    if (user_data_drops.occurred(executor.now())) {
      logger.warn("control message of {} bytes exceeds {} bytes: sent without client_user_data (the "
                  "operator's client_user_data for this vehicle is too large; repeats are counted, one "
                  "line every {})",
                  json_buffer.size(), max_payload_bytes, format_span(user_data_drops.period()));
    }
    outgoing.client_user_data.reset();
    ++stats.control_user_data_dropped;
    encode_control_message(outgoing, json_buffer);
    sent = vehicle_connection->send(json_buffer, outgoing.ack);
  }
  if (!sent) {
    // A vehicle that stopped reading was just closed, and the close said why; anything
    // else is a surprise worth its own line.
    if (sent.error().code != PeerError::not_reading) {
      logger.error("control message of {} bytes not sent: {}", json_buffer.size(), sent.error().message());
    }
    return;
  }
  ++stats.control_frames_sent;
  control_sent = true;
  last_sent_controller = outgoing.controller;
  OCP_INVARIANT(json_buffer.size() <= max_payload_bytes, "a control frame is never above 16 KiB");
}

}  // namespace ocp
