#pragma once
// StreamerCore: the complete vehicle-side behaviour of the OCP Streamer (SPEC §2, §3, §5, §6,
// §8) as a sans-IO state machine. It never touches a socket or a clock: time comes from the
// injected Executor, the vehicle client is an ocp::ByteStream (in-memory pipe or TCP — same
// code), and the Player is reached through an ocp::Link.
//
// Call order:
//   StreamerCore core(executor, config, logger);
//   core.set_link(&channel.to_player());         // where feedback, video and pongs go
//   auto subscription = core.events().subscribe(…); // optional, at any time
//   core.start();                                 // control ticker, frame loop, cameras
//   … core.accept_vehicle_connection(stream) whenever a vehicle connects (TCP front / pipe)
//   … core.handle_link_message(message) for everything the Player sends (OperatorControl, Ping)
//   core.stop();
//
// Threading: single-threaded. Every call and every executor callback must happen on the
// executor's thread (VirtualExecutor: the caller; AsioExecutor: the io_context thread).
//
// Timing rules (exact in virtual time; t0 = the executor's time at start(), or the t0 given to it):
// * ack_time = (now − t0) in µs + ack_time_offset (u64, wraps; never a double).
// * Control tick at t0 + k·control_period (absolute deadlines, PeriodicTimer), or at the
//   deadlines of a shared ControlTicker's slot (use_control_ticker). A tick sends a
//   control frame only while a vehicle is connected; faults are evaluated at every tick.
// * NoControlMessage: raised at the first tick where now − last operator message arrival >
//   no_control_timeout (measured from t0 when none ever arrived); cleared as soon as the next
//   operator message arrives (and re-evaluated on every tick).
// * InvalidMac: evaluated per operator message: active from a message whose returned pair is
//   missing or fails AckMac::verify until a message whose pair is valid. Before the first
//   operator message it is NOT raised (NoControlMessage covers a silent operator).
// * HighLatency: re-evaluated at every tick (and on every valid pair) from the newest valid
//   pair: latency = now − (ack_time − ack_time_offset), active while latency > latency_limit.
// * OperatorStationHasError: active while the latest operator message's sender_faults is
//   non-empty.
// * ControlThreadChannelSlow: operator messages enter an internal queue drained by the
//   control path (immediately, unless set_control_thread_stalled(true)); evaluated on every
//   enqueue and every tick: active while backlog > control_queue_limit or the oldest queued
//   message is older than control_queue_max_age.
// * CameraLost: each camera with drop_detector is checked on every control tick: active while
//   any such camera has produced no frame for > camera_drop_timeout (measured from start() for
//   a camera that never produced one). missing_cameras (telemetry and feedback) names exactly
//   those cameras, in configuration order, as of the latest tick. Camera k-th frame is due at
//   t0 + round(k·1e6/fps) µs; a stalled camera keeps its schedule but produces nothing.
// * Events due at the same microsecond run in scheduling order: a camera frame or frame-loop
//   iteration due at the same time as a tick runs before that tick (it was scheduled earlier).
// * Frame loop at frame_rate_hz (absolute deadlines). Each iteration sends one
//   StreamerFeedback. inject_frame_loop_stall(d): the next iteration is blocked for d (no
//   feedback while blocked); it completes at its start + d, then sends its feedback. If
//   d > streamer_slow_threshold, StreamerSlow is raised when that iteration completes, and is
//   cleared when the next normal iteration completes (the next frame deadline after the stall).
// * VehicleNoResponse: active exactly while no vehicle is connected (from start()).
// * Connections: one active; a second accepted stream is closed at once ("refused vehicle
//   connection from <new>: <active> is already connected") — unless the active one's peer has
//   already hung up (ByteStream::peer_hung_up: its close is still queued, e.g. after the
//   process was stopped), which is then closed and the new one accepted. Control frames are encoded per
//   tick straight into the active connection, so nothing built for a previous connection
//   reaches a new one; the first frame a new vehicle gets is the first tick after accept.
// * Bad vehicle input (SPEC §2): an inbound frame > 16 KiB is drained, counted and logged, the
//   connection kept; malformed JSON, non-object, missing/wrong-typed field or EOF inside a
//   frame closes it with the codec's Error::message() as the close reason (stats + log).
// * A control message that would exceed 16 KiB (only huge client_user_data can do that) is
//   sent without client_user_data, with a warning: once, then a count every 5 s while the
//   operator keeps sending it (ocp/log_limiter.hpp RepeatedWarning).
// * Vehicle read timeout: the connection is closed when no byte arrived for
//   vehicle_read_timeout (between frames as well as inside one).
// * A vehicle that stops reading is closed (PeerError::not_reading) once it has taken none of
//   the control frames waiting for it for 10 s, or they would exceed
//   vehicle_write_queue_limit_bytes (framed_connection.hpp: the same rule as :4001); the
//   Streamer carries on.
// * Events (events()): WireFrame for every control frame out and response in, FaultEvent on
//   every vehicle-side fault change, ConnectionEvent on open / close / refuse, and one
//   LatencySample per control tick. Nothing is built while nobody subscribes.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ocp/byte_stream.hpp"
#include "ocp/link.hpp"
#include "ocp/error.hpp"
#include "ocp/event_bus.hpp"
#include "ocp/framed_connection.hpp"
#include "ocp/executor.hpp"
#include "ocp/faults.hpp"
#include "ocp/link_messages.hpp"
#include "ocp/log.hpp"
#include "ocp/mac.hpp"
#include "ocp/messages.hpp"
#include "ocp/time.hpp"

namespace ocp {

class ControlTicker;

struct CameraConfig {
  std::string name;
  double fps = 30.0;
  bool drop_detector = true;            // false → never raises CameraLost, never "missing"
  std::uint32_t frame_size_bytes = 25000;
};

struct StreamerConfig {
  std::string name = "vehicle";
  Micros control_period{10'000};
  Micros no_control_timeout{1'000'000};
  Micros vehicle_read_timeout{2'000'000};
  Micros camera_drop_timeout{200'000};
  Micros streamer_slow_threshold{500'000};
  Micros latency_limit{500'000};
  double frame_rate_hz = 30.0;                   // Streamer frame loop = feedback rate
  std::vector<CameraConfig> cameras{CameraConfig{"front"}};
  std::size_t control_queue_limit = 20;          // ControlThreadChannelSlow backlog N
  Micros control_queue_max_age{100'000};
  std::uint64_t ack_time_offset = 0;             // conformance runs use ≥ 2^53
  std::size_t vehicle_write_queue_limit_bytes = default_write_queue_limit_bytes;
  std::optional<MacKey> mac_key;                 // nullopt → random_mac_key()
};

struct StreamerStats {
  // Vehicle side.
  std::uint64_t control_frames_sent = 0;
  std::uint64_t vehicle_responses_received = 0;
  std::uint64_t vehicle_bytes_in = 0;
  std::uint64_t vehicle_bytes_out = 0;
  std::uint64_t oversized_frames_dropped = 0;
  std::uint64_t control_user_data_dropped = 0;    // control frames sent without oversized user data
  std::uint64_t connections_accepted = 0;
  std::uint64_t connections_refused = 0;         // second connection while one was active
  std::uint64_t connections_closed = 0;          // active connections that ended (any reason)
  std::optional<CloseReason> last_close_reason;
  // Operator side.
  std::uint64_t operator_messages_received = 0;
  std::uint64_t invalid_returned_pairs = 0;
  std::uint64_t feedback_sent = 0;
  std::uint64_t video_frames_sent = 0;
  std::uint64_t pongs_sent = 0;
  std::uint64_t control_ticks = 0;
  std::uint64_t frame_loop_iterations = 0;
};

class StreamerCore {
 public:
  StreamerCore(Executor& executor, StreamerConfig config, Logger logger);
  ~StreamerCore();
  StreamerCore(const StreamerCore&) = delete;
  StreamerCore& operator=(const StreamerCore&) = delete;

  void start();   // control ticker (absolute 10 ms deadlines), frame loop, cameras
  // start() with t0 = min(t0, now): Streamers started together on one executor pass one t0
  // (World does), so their frame loops and cameras fall on the same instants, as they do in
  // virtual time — one wake-up per frame for them all instead of one per Streamer.
  void start(SimTime t0);
  void stop();    // stops timers and closes the vehicle connection

  void set_link(Link* to_player);                     // where feedback, video, pongs go
  // Before start(): tick on a ControlTicker shared with other Streamers of this executor
  // instead of a timer of its own (fleet scale; see control_ticker.hpp). Used only when its
  // period is control_period; the ticker must outlive this core. nullptr: own timer.
  void use_control_ticker(ControlTicker* ticker);
  void handle_link_message(LinkMessage&& message);    // from the Player (OperatorControl, Ping)
  void accept_vehicle_connection(std::shared_ptr<ByteStream> stream);  // TCP front or pipe

  void set_camera_stalled(std::string_view camera, bool stalled);
  void inject_frame_loop_stall(Micros duration);
  void set_control_thread_stalled(bool stalled);      // lets the control queue back up

  // Conformance testing (the `ocp_conformance vehicle` suite plays this Streamer against a
  // client under test and needs to shape what goes on the wire):
  // * Paused control output: ticks still run (faults, latency samples) but write no control
  //   frame, so a client can be watched while control pauses or fed hand-made frames only.
  void set_control_output_paused(bool paused);
  bool control_output_paused() const;
  // * Writes `bytes` (normally a whole frame: length prefix + payload, possibly oversized or
  //   deliberately odd) to the vehicle as-is: cut at the byte offsets in `cuts` (ascending,
  //   inside the bytes) into pieces written `gap` apart, on the executor. Publishes one
  //   WireFrame out (length prefix read from the first 4 bytes, payload = the rest) when the
  //   first piece is written. Pieces due after the connection changed are dropped. Error:
  //   no vehicle connected (LocalError::not_connected), or what the first write returned.
  [[nodiscard]] Status write_raw_to_vehicle(std::string bytes, std::vector<std::size_t> cuts = {},
                                            Micros gap = Micros{0});
  // * Closes the active vehicle connection from the server side (LocalError::shut_down), as
  //   a Streamer going away would; the client is expected to reconnect. No-op without one.
  void close_vehicle_connection();
  // Everything this Streamer does, as typed events (see the header comment).
  EventBus& events();

  const FaultSet& faults() const;                     // vehicle-side (receiver) faults
  std::optional<std::uint64_t> latency_ms() const;    // nullopt until a valid pair returned
  bool vehicle_connected() const;
  std::string vehicle_peer() const;                   // "" when none
  const StreamerStats& stats() const;
  const StreamerConfig& config() const;
  // Latest pair echoed by the vehicle (what SEI carries); nullopt before the first response.
  std::optional<AckPair> latest_echoed_pair() const;
  // Controller in the last control frame sent to the vehicle (nullopt: none sent, or null).
  std::optional<Controller> last_sent_controller() const;

 private:
  struct Impl;   // private state, split by concern over streamer_sim/core (streamer_impl.hpp)
  std::unique_ptr<Impl> impl_;
};

}  // namespace ocp
