#pragma once
// Private state of PlayerCore, shared by the .cpp files that implement it:
//   player_core.cpp   — lifecycle, vehicles, link messages, getters
//   frame_loop.cpp    — the per-frame control messages and VehicleOcpShared publication
//   client_data.cpp   — client data sources, locking, echo, the tcp client connection
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ocp/framed_connection.hpp"
#include "ocp/log_limiter.hpp"
#include "player/player_core.hpp"
#include "source_lock.hpp"
#include "vehicle_link.hpp"

namespace ocp {

struct PlayerCore::Impl {
  Impl(Executor& executor_in, PlayerConfig config_in, Logger logger_in);

  // frame_loop.cpp
  void on_frame();
  void refresh_shared(SimTime now);
  void on_ping();
  std::optional<std::string> resolve_active_vehicle() const;
  SimTime measured_since(const VehicleLink& link) const;

  // client_data.cpp
  void on_client_data(ClientSource source, const ClientOcpShared& data);
  void apply_client_data(ClientSource source, const ClientOcpShared& data);
  void stop_all_client_data();
  void summarise_repeated_warnings(SimTime now);   // every frame: the limiters' summaries
  std::optional<AckPair> echo_pair(const VehicleLink& link) const;
  void accept_client(std::shared_ptr<ByteStream> stream);
  void on_client_closed(const CloseReason& reason);
  void send_to_client(const VehicleOcpShared& shared);
  Status write_raw_to_client(std::string bytes, std::vector<std::size_t> cuts, Micros gap);

  // events.cpp: what the Player publishes (nothing is built while nobody listens).
  Component component() const { return Component{ComponentKind::player, config.name}; }
  void publish(EventBody body);
  void publish_sender_fault_changes(const std::string& vehicle, const FaultSet& before,
                                    const FaultSet& after);
  void publish_frame_changes(bool gamepad_plugged, const std::optional<std::string>& active);

  Executor& executor;
  PlayerConfig config;
  Logger logger;
  Micros frame_period;
  Gamepad gamepad;
  PlayerStats stats;
  EventBus events;
  // What the last frame published (GamepadChange, ActiveVehicleChange are edges).
  std::optional<bool> published_gamepad_plugged;
  std::optional<std::optional<std::string>> published_active_vehicle;

  std::map<std::string, VehicleLink> vehicles;  // name order: deterministic iteration
  SimTime started_at{0};
  bool running = false;
  PeriodicTimer frame_timer;
  PeriodicTimer ping_timer;

  SourceLock source_lock;
  std::optional<std::string> selected_vehicle;  // active_vehicle from client data
  std::optional<Controller> last_input;
  VehicleOcpShared last_shared;
  std::vector<SharedListener> shared_listeners;

  // Names already warned about, so a client or link repeating them at 100 Hz logs once; at
  // most WarnedNames::default_capacity each: a client sending ever-new names is summarised,
  // not remembered (log_limiter.hpp).
  WarnedNames warned_unknown_entries;
  WarnedNames warned_unknown_senders;
  WarnedNames warned_unknown_active;   // forgotten when a linked vehicle is selected

  std::shared_ptr<FramedConnection> client;      // the tcp source (:4001), one at a time
  ConnectionLogBudget connection_log;            // connection storms do not flood the log
  std::optional<CloseReason> last_client_close_reason;
  // The locked tcp client left and nobody returns pairs (SPEC §4.3): logged once, until a tcp
  // client sends client data again — not once per connection, which a storm would flood.
  bool tcp_lock_without_client_logged = false;
  std::string client_json_buffer;                // reused every frame
  std::optional<ClientFrameTooLarge> client_too_large;   // an episode of oversized frames: warned once
  bool client_output_paused = false;             // conformance testing: no VehicleOcpShared to the tcp client
};

}  // namespace ocp
