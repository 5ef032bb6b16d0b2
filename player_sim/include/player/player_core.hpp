#pragma once
// PlayerCore: the operator station (SPEC §4, §5 player part, §6 operator faults, §7, §8).
//
// Sans-IO: time comes from the injected Executor, vehicles are reached through Links (ocp/link.hpp)
// (the fake com channel) and the operator TCP client through a ByteStream (pipe or socket —
// same code). Nothing here reads a clock or opens a socket.
//
// Call order:
//   1. construct; add_vehicle() for each linked Streamer (the caller wires the reverse
//      direction of each link to handle_link_message(vehicle, …));
//   2. start(): the frame loop runs at frame_rate_hz (≤ 100 Hz, absolute deadlines), pings
//      go out every ping_period;
//   3. inputs at any time: handle_link_message (feedback, video+SEI, pong),
//      accept_client_connection (tcp source), handle_client_data (webview/plugin sources);
//   4. outputs every frame: one OperatorControl per non-monitor vehicle, and one
//      VehicleOcpShared to the tcp client (framed JSON) and to every shared listener;
//   5. stop(): timers stop, the tcp client is closed.
//
// Decisions where the SPEC leaves room:
//   * controller sent to a vehicle: the gamepad sample when it is the active vehicle and the
//     gamepad is plugged; the safe default controller when it is not active or the gamepad is
//     unplugged; nullopt when ocp_disable_gamepad is set for it.
//   * InputLost is raised on every control (non-monitor) vehicle whose gamepad is not disabled
//     while the gamepad is unplugged. Monitor links only carry NoFeedbackMessage.
//   * A client_user_data entry is that vehicle's complete client state: it replaces the
//     previous entry (an absent user_data means none, an absent pair means no echo, an absent
//     ocp_disable_gamepad means false). Vehicles without an entry keep their state. An absent
//     active_vehicle leaves the selection unchanged.
//   * After a source conflict (§4.3) user data and every external echo stop (returned_ack is
//     nullopt, no self-echo); active_vehicle and ocp_disable_gamepad keep their last values so
//     gamepad input is never routed somewhere the operator did not choose.
//   * Web view echo: the pair injected is the latest SEI pair when each web view message
//     arrives; it is echoed until the next web view message (a silent web view goes stale).
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ocp/byte_stream.hpp"
#include "ocp/client_source.hpp"
#include "ocp/link.hpp"
#include "ocp/error.hpp"
#include "ocp/event_bus.hpp"
#include "ocp/executor.hpp"
#include "ocp/faults.hpp"
#include "ocp/link_messages.hpp"
#include "ocp/log.hpp"
#include "ocp/messages.hpp"
#include "player/gamepad.hpp"

namespace ocp {

// What the log, the status line and the web view say while tcp_lock_without_client() (SPEC §4.3).
inline constexpr std::string_view tcp_lock_without_client_text =
    "source tcp locked, no client connected: no pair is returned";

// A ClientOcpShared carrying no client data — no active_vehicle and no client_user_data entry
// with any field, e.g. {} — is a keep-alive (SPEC §4.2): a read-only dashboard sends it to
// stay connected, so it neither locks a source nor counts as that source's data (§4.3).
bool is_keep_alive(const ClientOcpShared& data);
// The same rule for one source. A web view call is never a keep-alive for a vehicle it names
// (SPEC §4.2 Decision: the Player injects the pair into every call), so for the web view only a
// call naming nothing — no active_vehicle, no client_user_data entry, e.g. {} — is one.
bool is_keep_alive(ClientSource source, const ClientOcpShared& data);

inline constexpr double max_player_frame_rate_hz = 100.0;

struct PlayerConfig {
  std::string name = "player";
  double frame_rate_hz = 100.0;          // control messages at this rate, capped at 100 Hz
  Micros no_feedback_timeout{1'000'000};
  Micros ping_period{100'000};
  bool fleet = false;                    // without a fleet exactly one Streamer may be linked
  Micros client_read_timeout{2'000'000}; // :4001 client silence → close (SPEC §4.2 same rules as §2); 0 = off
};

// The frame period actually used: 1 s / min(frame_rate_hz, 100), rounded to whole µs.
Micros player_frame_period(const PlayerConfig& config);

struct PlayerStats {
  std::uint64_t frames = 0;
  std::uint64_t control_messages_sent = 0;
  std::uint64_t pings_sent = 0;
  std::uint64_t pongs_received = 0;
  std::uint64_t feedback_received = 0;
  std::uint64_t video_frames_received = 0;
  std::uint64_t shared_published = 0;           // VehicleOcpShared objects built
  std::uint64_t client_messages_received = 0;   // decoded ClientOcpShared, all sources
  std::uint64_t client_messages_ignored = 0;    // dropped because client data is stopped
  std::uint64_t client_keep_alives = 0;         // ClientOcpShared without client data (§4.2)
  std::uint64_t client_oversized_frames = 0;    // drained inbound frames on :4001
  std::uint64_t client_connections_accepted = 0;
  std::uint64_t client_connections_refused = 0; // second client while one is active
  std::uint64_t client_connections_closed = 0;  // closed by us or by the peer
  std::uint64_t client_frames_sent = 0;
  std::uint64_t client_bytes_out = 0;           // every byte written to the tcp client (headers, raw writes)
  std::uint64_t client_frames_too_large = 0;    // VehicleOcpShared over 16 KiB, not sent
  std::uint64_t source_conflicts = 0;
  std::uint64_t unknown_vehicle_entries = 0;
};

// The :4001 client's VehicleOcpShared is over the frame limit (SPEC §2: never sent), so the
// client receives nothing until it fits again — e.g. from 17 vehicles up with the defaults.
struct ClientFrameTooLarge {
  std::size_t bytes = 0;          // the latest VehicleOcpShared payload
  std::size_t limit = 0;          // the payload limit (16 384)
  std::uint64_t frames = 0;       // frames not sent since the episode began
  std::size_t vehicles = 0;       // vehicle entries in it
};
// "VehicleOcpShared too large: 19574 B > 16384 B, not sent to the client (42 frames)"
std::string describe(const ClientFrameTooLarge& too_large);

class PlayerCore {
 public:
  PlayerCore(Executor& executor, PlayerConfig config, Logger logger);
  ~PlayerCore();
  PlayerCore(const PlayerCore&) = delete;
  PlayerCore& operator=(const PlayerCore&) = delete;

  void start();
  void stop();
  bool running() const;

  // Links a Streamer. `to_streamer` must outlive the PlayerCore (or stop()). A monitor link
  // receives feedback and video but is sent no OperatorControl. Without config.fleet a second
  // vehicle is a configuration error; duplicate names are errors too.
  [[nodiscard]] Status add_vehicle(const std::string& name, Link* to_streamer,
                                   bool monitor = false);
  // Unlinks a vehicle while the Player is stopped, so that a caller taking back the link it
  // gave (a World whose start failed part-way) leaves no pointer to it behind. Error while
  // running (the frame loop relies on vehicles only being added then) or for an unknown name.
  [[nodiscard]] Status remove_vehicle(const std::string& name);
  // Everything arriving from that vehicle's Streamer (feedback, video frames, pongs).
  void handle_link_message(const std::string& vehicle, LinkMessage&& message);

  // The `tcp` source: a connected :4001 client (a TCP socket or an in-memory pipe end).
  void accept_client_connection(std::shared_ptr<ByteStream> stream);
  // The `webview` and `plugin` sources (tcp goes through the stream). Passing tcp here is
  // accepted too and treated as the tcp source.
  void handle_client_data(ClientSource source, const ClientOcpShared& data);

  // Selects the active vehicle from the station itself (a scenario or the operator UI), as
  // active_vehicle in client data would, without counting as client data: no source locks.
  // nullopt clears the selection (one control vehicle is then active again, several none).
  void select_vehicle(std::optional<std::string> vehicle);

  using SharedListener = std::function<void(const VehicleOcpShared&)>;
  // Web view / plugin consumers: called every frame with the object of SPEC §4.1.
  void add_shared_listener(SharedListener listener);

  Gamepad& gamepad();
  const Gamepad& gamepad() const;

  // Conformance testing (the `ocp_conformance operator` suite plays this Player against an
  // operator client under test and needs to shape its :4001 wire):
  // * Paused client output: frames still run (controls, faults, the web view's listeners) but
  //   no VehicleOcpShared is written to the tcp client, so its keep-alives can be watched.
  void set_client_output_paused(bool paused);
  bool client_output_paused() const;
  // * Closes the tcp client connection from the server side (LocalError::shut_down), as a
  //   Player going away would; the client is expected to reconnect. No-op without one.
  void close_client_connection();
  // * Writes `bytes` to the tcp client as-is (normally whole frames: length prefix + payload,
  //   possibly oversized, several back to back, or deliberately odd): cut at the byte offsets
  //   in `cuts` (ascending, inside the bytes) into pieces written `gap` apart, on the executor.
  //   Pause client output first, or the frame loop's frames land between the pieces. Publishes
  //   one WireFrame out per frame found in the bytes (length prefix read from its first 4
  //   bytes, payload = what follows, up to that length) when the first piece is written, so a
  //   wire log shows every frame sent. Pieces due after the connection changed are dropped.
  //   Error: no client connected (LocalError::not_connected), or what the first write returned.
  [[nodiscard]] Status write_raw_to_client(std::string bytes, std::vector<std::size_t> cuts = {},
                                           Micros gap = Micros{0});

  // Getters (for fronts, scenarios and tests).
  const PlayerConfig& config() const;
  std::vector<std::string> vehicles() const;       // in name order
  FaultSet sender_faults(const std::string& vehicle) const;   // as sent in the last frame
  const VehicleOcpShared& last_shared() const;
  std::optional<ClientSource> locked_source() const;
  bool client_data_stopped() const;     // source-locking conflict happened
  // The vehicle that receives gamepad input now (SPEC §7): the selected active_vehicle, or
  // the only control vehicle when none was selected; nullopt when no vehicle is active.
  std::optional<std::string> active_vehicle() const;
  std::optional<AckPair> latest_sei(const std::string& vehicle) const;
  bool client_connected() const;        // a tcp client is attached
  // SPEC §4.3 Decision: the lock belongs to the source kind, so after the locked tcp client
  // left nobody returns pairs until a new tcp client takes over. True in that state (locked
  // to tcp, no client, no source conflict); the Player logs it once when the client leaves,
  // and the status line and the web view show tcp_lock_without_client_text.
  bool tcp_lock_without_client() const;
  // While the tcp client's VehicleOcpShared is too large to send; nullopt when it fits (or
  // there is no client).
  const std::optional<ClientFrameTooLarge>& client_frame_too_large() const;
  // Names the "unknown vehicle" warnings remember so as to warn once each: bounded
  // (WarnedNames, ocp/log_limiter.hpp), whatever names a client sends.
  std::size_t remembered_unknown_names() const;
  const std::optional<CloseReason>& last_client_close_reason() const;
  // Everything the Player does, as typed events: sender FaultEvents per vehicle, GamepadChange,
  // ActiveVehicleChange, SourceLocked / SourceConflict, and the :4001 client's WireFrames and
  // ConnectionEvents. Nothing is built while nobody subscribes.
  EventBus& events();
  const PlayerStats& stats() const;

 private:
  struct Impl;   // private state, split by concern over player_sim/core (player_impl.hpp)
  std::unique_ptr<Impl> impl_;
};

}  // namespace ocp
