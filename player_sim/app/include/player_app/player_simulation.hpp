#pragma once
// What `player_sim` runs: a Player whose operator API is a real TCP port, linked through fake
// com channels to N simulated vehicles (a StreamerCore each, with the reference vehicle
// client attached in-process), a fleet when N > 1. Real time on an AsioExecutor. Tests build
// it directly; the executable adds the command line and signals.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "ocp/asio_executor.hpp"
#include "ocp/com_channel.hpp"
#include "ocp/latency_window.hpp"
#include "ocp/log.hpp"
#include "ocp/plugin_params.hpp"
#include "player_app/player_front.hpp"
#include "world/world.hpp"
#include "sim_app/gamepad_script.hpp"

namespace ocp {

struct PlayerSimOptions {
  std::vector<std::string> vehicles{"vehicle"};
  PluginParams plugin_params;            // ocp_player_tcp_port, ocp_tcp_allow_remote, latency_limit
  std::vector<CameraConfig> cameras;     // per vehicle; empty: the default (front, 30 fps)
  Impairments link;                      // both directions of every fake com channel
  std::uint64_t seed = 1;
  sim::GamepadScript gamepad;            // the operator station's gamepad (default: drive)
  double frame_rate_hz = 100.0;          // Player frame rate (capped at 100)
  std::uint64_t ack_time_offset = 0;     // added to every ack_time of every Streamer (SPEC §5)
};

class PlayerSimulation {
 public:
  PlayerSimulation(AsioExecutor& executor, PlayerSimOptions options, LogSink sink);
  ~PlayerSimulation();
  PlayerSimulation(const PlayerSimulation&) = delete;
  PlayerSimulation& operator=(const PlayerSimulation&) = delete;

  // Listens, then starts the world (so a busy port fails before anything runs). Errors: the
  // port in use (TcpServer::listen), or a configuration error from World::start.
  [[nodiscard]] Status start();
  void stop();

  std::uint16_t port() const { return front_.port(); }
  std::string address() const { return front_.address(); }
  World& world() { return world_; }
  PlayerCore& player() { return world_.player(); }

  // The once-per-second status line; rates are per second since the previous call. Per
  // vehicle it keeps two views apart: the simulated Streamer's own (latency min/avg/max over
  // the second, its faults) and what the operator client is sent (receiver_fault and
  // sender_fault of the last VehicleOcpShared) — they differ when the link loses feedback.
  std::string status_line();

 private:
  AsioExecutor& executor_;
  PlayerSimOptions options_;
  Logger logger_;
  World world_;
  PlayerFront front_;
  PeriodicTimer latency_sampler_;
  std::map<std::string, LatencyWindow> latency_windows_;
  struct Previous {
    SimTime time{0};
    std::uint64_t client_frames_sent = 0;
    std::uint64_t client_messages_received = 0;
  } previous_;
};

}  // namespace ocp
