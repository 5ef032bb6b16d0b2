#pragma once
// What `player_sim` runs: a Player whose operator API is a real TCP port, linked through fake
// com channels to N simulated vehicles (a StreamerCore each, with the reference vehicle
// client attached in-process), a fleet when N > 1. Real time on an AsioExecutor. Tests build
// it directly; the executable adds the command line and signals.
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ocp/asio/executor.hpp"
#include "ocp/com_channel.hpp"
#include "sim_app/latency_window.hpp"
#include "ocp/log.hpp"
#include "sim_app/plugin_params.hpp"
#include "player_app/webview_server.hpp"
#include "world/world.hpp"
#include "sim_app/gamepad_script.hpp"
#include "sim_app/pair_rejection_notes.hpp"
#include "sim_app/simulated_world_options.hpp"
#include "sim_app/tcp_front.hpp"
#include "sim_app/udp_com.hpp"

namespace ocp {

struct PlayerSimOptions : sim_app::SimulatedWorldOptions {   // ocp_player_tcp_port is the operator API's
  std::vector<std::string> vehicles{"vehicle"};
  double frame_rate_hz = 100.0;          // Player frame rate (capped at 100)
  // --vehicle-tcp: these vehicles get a vehicle-side TCP API on the port (0 = free port)
  // instead of the in-process reference vehicle client.
  std::map<std::string, std::uint16_t> vehicle_tcp_ports;
  std::optional<WebviewOptions> webview;  // the web view endpoint; nullopt = none
  // --vehicle NAME=udp://HOST:PORT: that vehicle is a real Streamer (streamer_sim --com-listen)
  // over a UDP com channel, instead of a simulated one; to_streamer impairments apply here.
  std::map<std::string, boost::asio::ip::udp::endpoint> udp_vehicles;
  com::ComKey com_key;                    // empty: --com-insecure
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

  std::uint16_t port() const { return front_->port(); }
  std::string address() const { return front_->address(); }
  // The web view port (0 without one) and a --vehicle-tcp vehicle's port (0 for others).
  std::uint16_t webview_port() const { return webview_ ? webview_->port() : 0; }
  WebviewServer* webview() { return webview_.get(); }
  std::uint16_t vehicle_port(const std::string& vehicle) const;
  World& world() { return world_; }
  PlayerCore& player() { return world_.player(); }
  sim_app::UdpComEndpoint* com(const std::string& vehicle);   // nullptr unless a UDP vehicle

  // The once-per-second status line; rates are per second since the previous call. Per
  // vehicle it keeps two views apart: the simulated Streamer's own (latency min/avg/max over
  // the second, its faults) and what the operator client is sent (receiver_fault and
  // sender_fault of the last VehicleOcpShared) — they differ when the link loses feedback.
  std::string status_line();

 private:
  void attach_remote_streamer(const std::string& vehicle);

  AsioExecutor& executor_;
  PlayerSimOptions options_;
  Logger logger_;
  World world_;
  sim_app::PairRejectionNotes pair_notes_;   // why loops do not close: status line, web view
  std::unique_ptr<sim_app::TcpFront> front_;
  std::map<std::string, std::unique_ptr<sim_app::TcpFront>> vehicle_fronts_;
  std::unique_ptr<WebviewServer> webview_;
  std::map<std::string, std::unique_ptr<sim_app::UdpComEndpoint>> coms_;
  PeriodicTimer latency_sampler_;
  std::map<std::string, LatencyWindow> latency_windows_;
  struct Previous {
    SimTime time{0};
    std::uint64_t client_frames_sent = 0;
    std::uint64_t client_messages_received = 0;
  } previous_;
};

}  // namespace ocp
