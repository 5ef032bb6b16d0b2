#pragma once
// Per-vehicle state of the Player: what arrived from that Streamer (feedback, SEI pairs,
// pongs), what the operator client said about it, and the operator-side fault rules.
#include <cstdint>
#include <optional>
#include <string>

#include "ocp/link.hpp"
#include "ocp/faults.hpp"
#include "ocp/link_messages.hpp"
#include "ocp/messages.hpp"
#include "ocp/time.hpp"

namespace ocp {

// What the locked client source last said about one vehicle (see player_core.hpp Decisions).
struct VehicleClientState {
  std::optional<RawJson> user_data;
  bool disable_gamepad = false;
  std::optional<AckPair> returned_pair;  // tcp/plugin: the pair it echoed; webview: injected
};

struct VehicleLink {
  std::string name;
  Link* to_streamer = nullptr;
  bool monitor = false;
  SimTime linked_at{0};

  // From the Streamer.
  std::optional<AckPair> latest_sei;
  std::optional<StreamerFeedback> last_feedback;
  SimTime feedback_arrived_at{0};
  std::optional<std::uint64_t> newest_pong_id;
  std::uint64_t ping_latency_ms = 0;

  // To the Streamer.
  std::uint64_t next_control_sequence = 0;
  std::uint64_t next_ping_id = 0;

  VehicleClientState client;
  FaultSet sender_faults;  // as evaluated in the latest frame

  void on_feedback(StreamerFeedback&& feedback, SimTime now);
  void on_video_frame(const VideoFrame& frame);
  void on_pong(const Pong& pong, SimTime now);
};

// Inputs of the operator-side fault rules (SPEC §6) for one vehicle at one frame.
struct SenderFaultInputs {
  SimTime now{0};
  SimTime measured_since{0};     // start of NoFeedbackMessage measurement when none arrived yet
  Micros no_feedback_timeout{1'000'000};
  bool gamepad_plugged = true;
  bool is_active = false;
};

// InputLost, NoFeedbackMessage, VehicleControlInactive for `link` (monitors: only NoFeedback).
FaultSet evaluate_sender_faults(const VehicleLink& link, const SenderFaultInputs& inputs);

// The VehicleOcpShared entry of SPEC §4.1 for `link` at `now`.
VehicleFeedback build_vehicle_feedback(const VehicleLink& link, SimTime now, SimTime measured_since);
// The same, written over last frame's `entry` in place (keeps its strings' and vectors' buffers).
void refresh_vehicle_feedback(VehicleFeedback& entry, const VehicleLink& link, SimTime now, SimTime measured_since);

}  // namespace ocp
