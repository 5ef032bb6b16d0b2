// The oracle's fault model, latency-loop samples and liveness (oracle.hpp). Each SPEC §6
// condition is computed here from observed events and the world's model, then compared with
// what the world reports, at every control tick of the vehicle (the LatencySample that ends
// the tick: the tick's faults are already published). Tolerances, as docs/campaigns.md states:
//   * VehicleNoResponse, NoControlMessage, HighLatency: exact, at the tick where they are due;
//     HighLatency has a 1 ms band because samples are in whole ms.
//   * NoFeedbackMessage: one Player frame (the Player evaluates per frame).
//   * CameraLost: active once a stalled, monitored camera has been silent longer than its
//     drop timeout; may stay up to timeout + two frames + one tick after the stall.
//   * StreamerSlow, ControlThreadChannelSlow: only inside (and shortly after) stall windows.
//   * InvalidMac and OperatorStationHasError carry what the event stream does not show (the
//     returned pair, the sender faults in flight): liveness checks them.
#include <algorithm>

#include "oracle_state.hpp"
#include "world/world.hpp"

namespace ocp::campaign {

namespace {

bool inside(const std::vector<Window>& windows, SimTime now, Micros before, Micros after) {
  return std::any_of(windows.begin(), windows.end(),
                     [&](const Window& w) { return now >= w.start - before && now <= w.end + after; });
}

bool worse(const Impairments& now, const Impairments& start) {
  return now.down || now.delay > start.delay || now.jitter > start.jitter ||
         now.loss_probability > start.loss_probability || now.burst_loss ||
         (now.bandwidth_bits_per_second > 0 && start.bandwidth_bits_per_second == 0) ||
         now.reorder_probability > start.reorder_probability;
}

}  // namespace

void Oracle::on_latency_sample(const Event& event, const LatencySample& sample) {
  if (event.component.kind != ComponentKind::streamer) return;
  VehicleState& state = vehicle(event.component.name);
  if (state.spec == nullptr) return;
  const SimTime now = event.time - origin_;
  // Latency loop: the sample is now − ack_time of a pair this Streamer issued and the vehicle
  // echoed with its MAC, and never an older pair than one already accepted.
  if (sample.latency_ms && tolerances_.judge_timing) {
    const auto ms = static_cast<std::int64_t>(*sample.latency_ms);
    const SimTime newest_issue = now - Micros{ms * 1000};   // issued in (now − (ms+1) ms, now − ms ms]
    const SimTime oldest_issue = newest_issue - Micros{1000};   // exclusive
    auto found = std::upper_bound(state.issued.begin(), state.issued.end(), newest_issue,
                                  [](SimTime t, const IssuedPair& pair) { return t < pair.issued; });
    const bool covered = !state.issued.empty() && state.issued.front().issued <= oldest_issue;
    if (found == state.issued.begin() || (found - 1)->issued <= oldest_issue) {
      if (covered) {
        report(Check::latency_loop, now, state.name,
               "latency " + std::to_string(ms) + " ms: no pair was issued " + std::to_string(ms) + " ms ago");
      }
    } else {
      const IssuedPair& pair = *(found - 1);
      if (!pair.echoed_with_mac) {
        report(Check::latency_loop, now, state.name,
               "latency " + std::to_string(ms) + " ms from ack_time " + std::to_string(pair.ack_time) +
                   ", which the vehicle never echoed with its MAC");
      }
      if (state.newest_accepted && pair.issued < *state.newest_accepted) {
        report(Check::latency_loop, now, state.name,
               "latency " + std::to_string(ms) + " ms: an older pair (issued at " + std::to_string(pair.issued.count()) +
                   " us) replaced a newer one (issued at " + std::to_string(state.newest_accepted->count()) + " us)");
      }
      state.newest_accepted = std::max(state.newest_accepted.value_or(pair.issued), pair.issued);
    }
  }
  state.last_latency_ms = sample.latency_ms;
  if (tolerances_.judge_timing) {
    check_fault_model(state, now, sample);
    check_operator_faults(state, now);
    if (liveness_possible_ && !state.liveness_done && now >= liveness_at_) check_liveness(state, now, sample);
    if (operator_ && liveness_possible_ && now >= liveness_at_) check_operator_liveness(now);
  }
  // Counters about ten times a second (on the first vehicle's ticks), and at the end.
  if (world_ != nullptr && &state == vehicles_.begin()->second.get() && (now.count() / 10'000) % 10 == 0) {
    check_counters(*world_, now);
  }
}

void Oracle::check_fault_model(VehicleState& state, SimTime now, const LatencySample& sample) {
  const StreamerConfig& config = state.spec->streamer;
  const FaultBits& reported = state.reported_vehicle;
  auto expect = [&](FaultId id, bool should, const std::string& why) {
    if (reported.has(id) == should) return;
    report(Check::fault_model, now, state.name,
           std::string(fault_identifier(id)) + (should ? " not active though " : " active though ") + why, id, should);
  };
  expect(FaultId::VehicleNoResponse, !state.connected,
         state.connected ? "a vehicle is connected" : "no vehicle is connected");

  const Micros control_gap = now - state.last_control_delivered.value_or(SimTime{0});
  if (control_gap > config.no_control_timeout) {
    expect(FaultId::NoControlMessage, true, "no operator message for " + ms_text(control_gap));
  } else if (!inside(state.control_stalls, now, Micros{0}, config.control_period)) {
    expect(FaultId::NoControlMessage, false, "an operator message arrived " + ms_text(control_gap) + " ago");
  }

  const std::int64_t limit_us = config.latency_limit.count();
  if (!sample.latency_ms) {
    expect(FaultId::HighLatency, false, "no latency was measured yet");
  } else {
    const auto ms = static_cast<std::int64_t>(*sample.latency_ms);
    if (ms * 1000 > limit_us) expect(FaultId::HighLatency, true, "latency " + std::to_string(ms) + " ms > limit");
    if ((ms + 1) * 1000 <= limit_us) expect(FaultId::HighLatency, false, "latency " + std::to_string(ms) + " ms <= limit");
  }

  bool camera_may = false, camera_must = false;
  std::string camera_why;
  for (const CameraWatch& camera : state.cameras) {
    const Micros after = config.camera_drop_timeout + 2 * camera.frame_period + config.control_period;
    if (inside(camera.stalls, now, Micros{0}, after)) camera_may = true;
    for (std::size_t w = 0; w < camera.stalls.size(); ++w) {
      const Window& stall = camera.stalls[w];
      if (camera.certain[w] && now - stall.start > config.camera_drop_timeout + config.control_period && now < stall.end) {
        camera_must = true;
        camera_why = "camera " + camera.name + " stalled " + ms_text(now - stall.start) + " ago";
      }
    }
    // A frame-loop stall holds every camera back.
    if (inside(state.frame_stalls, now, Micros{0}, after)) camera_may = true;
  }
  if (camera_must) expect(FaultId::CameraLost, true, camera_why);
  else if (!camera_may) expect(FaultId::CameraLost, false, "no monitored camera was stalled");

  const Micros frame_period{static_cast<std::int64_t>(1e6 / config.frame_rate_hz)};
  if (!inside(state.frame_stalls, now, Micros{0}, config.streamer_slow_threshold + 2 * frame_period + config.control_period)) {
    expect(FaultId::StreamerSlow, false, "the frame loop was not stalled");
  }
  if (!inside(state.control_stalls, now, Micros{0}, config.control_queue_max_age + 2 * config.control_period + tolerances_.player_frame)) {
    expect(FaultId::ControlThreadChannelSlow, false, "the control thread was not stalled");
  }
}

void Oracle::check_operator_faults(VehicleState& state, SimTime now) {
  if (!state.last_feedback_delivered) return;   // the Player's start-up is its own business
  const Micros timeout = scenario_.world.player.no_feedback_timeout;
  const Micros gap = now - *state.last_feedback_delivered;
  const bool reported = state.reported_operator.has(FaultId::NoFeedbackMessage);
  if (gap > timeout + tolerances_.player_frame && !reported) {
    report(Check::fault_model, now, state.name, "NoFeedbackMessage not active though no feedback for " + ms_text(gap),
           FaultId::NoFeedbackMessage, true);
  } else if (gap > tolerances_.player_frame && gap <= timeout && reported) {
    report(Check::fault_model, now, state.name, "NoFeedbackMessage active though feedback arrived " + ms_text(gap) + " ago",
           FaultId::NoFeedbackMessage, false);
  }
}

// Once every disturbance has ended (quiet_point + liveness_bound): every fault the disturbances
// could cause has cleared and the loop is closed. What the world itself keeps up is allowed:
// a monitor never gets control; a vehicle that is not selected, or whose operator station
// still reports a fault, has OperatorStationHasError; a source conflict stops the loop (§4.3).
void Oracle::check_liveness(VehicleState& state, SimTime now, const LatencySample& sample) {
  state.liveness_done = true;
  liveness_checked_ = true;
  if (state.spec->monitor || state.misbehaving_at_end) return;
  if (worse(state.now_to_streamer, state.start_to_streamer) || worse(state.now_to_player, state.start_to_player)) return;
  const bool loop_may_break = source_conflict_;
  std::string stuck;
  for (std::size_t f = 0; f < fault_count; ++f) {
    const auto id = static_cast<FaultId>(f);
    if (!state.reported_vehicle.has(id)) continue;
    if (id == FaultId::OperatorStationHasError && !state.reported_operator.empty()) continue;
    if ((id == FaultId::HighLatency || id == FaultId::InvalidMac) && loop_may_break) continue;
    stuck += std::string(fault_identifier(id)) + " ";
  }
  if (state.reported_operator.has(FaultId::NoFeedbackMessage)) stuck += "NoFeedbackMessage ";
  if (state.reported_operator.has(FaultId::InputLost) && gamepad_plugged_) stuck += "InputLost ";
  if (!stuck.empty()) {
    stuck.pop_back();
    report(Check::liveness, now, state.name,
           "still active " + ms_text(liveness_bound(scenario_)) + " after the last disturbance: " + stuck);
    return;
  }
  if (!loop_may_break && (!sample.latency_ms || static_cast<std::int64_t>(*sample.latency_ms) * 1000 >
                                                    state.spec->streamer.latency_limit.count())) {
    report(Check::liveness, now, state.name,
           "the latency loop is not closed " + ms_text(liveness_bound(scenario_)) + " after the last disturbance (latency " +
               (sample.latency_ms ? std::to_string(*sample.latency_ms) + " ms" : std::string("none")) + ")");
  }
}

}  // namespace ocp::campaign
