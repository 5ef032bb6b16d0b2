#pragma once
// StreamerCore's private state, shared by the files that implement it by concern:
//   streamer_core.cpp     — lifecycle and the public getters
//   vehicle_side.cpp      — accepting / refusing / losing the vehicle connection, responses
//   operator_side.cpp     — link messages from the Player, the control inbox, returned pairs
//   control_tick.cpp      — the 10 ms tick: fault evaluation and the OcpControlMessage
//   feedback.cpp          — frame loop iterations (feedback, StreamerSlow) and video frames
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cameras.hpp"
#include "control_inbox.hpp"
#include "fault_tracker.hpp"
#include "frame_loop.hpp"
#include "latency_loop.hpp"
#include "ocp/framed_connection.hpp"
#include "ocp/log_limiter.hpp"
#include "streamer/control_ticker.hpp"
#include "streamer/streamer_core.hpp"

namespace ocp {

struct StreamerCore::Impl {
  Impl(Executor& executor, StreamerConfig config, Logger logger);

  // streamer_core.cpp
  void start(SimTime t0);   // t0 <= now
  void stop();

  // vehicle_side.cpp
  void accept_vehicle(std::shared_ptr<ByteStream> stream);
  void on_vehicle_response(VehicleResponseMessage&& response);
  void on_vehicle_closed(const CloseReason& reason);
  Status write_raw_to_vehicle(std::string bytes, std::vector<std::size_t> cuts, Micros gap);

  // operator_side.cpp
  void handle_link_message(LinkMessage&& message);
  void enqueue_operator_control(OperatorControl&& message);
  void drain_inbox();
  void apply_operator_control(streamer::QueuedControl&& queued);
  void evaluate_inbox_fault();

  // control_tick.cpp
  void on_control_tick(SimTime deadline);
  void evaluate_tick_faults(SimTime now);
  void build_control_message(SimTime now);
  void send_control_message();
  void summarise_user_data_drops(SimTime now);
  void summarise_pair_rejections(SimTime now);

  // feedback.cpp
  void on_frame_iteration(Micros took);
  void send_feedback();
  void send_video_frame(VideoFrame&& frame);
  void send_to_player(LinkMessage&& message);

  // Events (streamer_core.cpp): the component every event of this Streamer carries.
  Component component() const { return Component{ComponentKind::streamer, config.name}; }
  void publish_fault(FaultId id, bool active);
  void publish_latency_sample(SimTime deadline, SimTime now);
  // operator_side.cpp: why a returned pair was rejected, logged and published once an episode.
  void report_rejected_pair(const AckPair& rejected);

  Executor& executor;
  StreamerConfig config;
  Logger logger;
  StreamerStats stats;
  EventBus events;
  Link* to_player = nullptr;                      // the link's direction towards the Player (feedback, video)

  streamer::FaultTracker faults;
  streamer::LatencyLoop latency_loop;
  streamer::ControlInbox inbox;
  streamer::CameraSet cameras;
  streamer::FrameLoop frame_loop;
  PeriodicTimer control_timer;
  ControlTicker* control_ticker = nullptr;       // shared with other Streamers, instead of control_timer
  ControlTicker::Member ticker_member;

  bool started = false;
  SimTime start_time{};

  // Vehicle side.
  ConnectionLogBudget connection_log;            // connection storms do not flood the log
  std::shared_ptr<FramedConnection> vehicle_connection;
  std::optional<AckPair> echoed_pair;            // latest pair echoed by the vehicle (→ SEI)
  std::optional<VehicleUserData> vehicle_data;   // latest vehicle user data …
  SimTime vehicle_data_arrived_at{};             // … and when it arrived

  // Operator side (as applied by the control path).
  SimTime last_operator_arrival{};               // start_time until the first message
  bool operator_message_seen = false;
  std::optional<Controller> operator_controller = Controller::safe_default();
  std::optional<RawJson> operator_user_data;
  bool control_thread_stalled = false;
  bool inbox_overflow_logged = false;
  bool pair_rejection_reported = false;          // this InvalidMac episode's first bad pair is told

  // Control path output.
  OcpControlMessage outgoing;                    // reused every tick
  std::string json_buffer;                       // reused every tick
  bool control_sent = false;
  bool control_output_paused = false;            // conformance: ticks write no control frame
  std::optional<Controller> last_sent_controller;
  std::vector<std::string> missing_cameras;      // as of the last evaluation
  RepeatedWarning user_data_drops;               // control messages sent without oversized user data
  RepeatedWarning pair_rejections;               // InvalidMac episodes: the first told, the rest summarised

  std::uint64_t feedback_sequence = 0;
};

}  // namespace ocp
