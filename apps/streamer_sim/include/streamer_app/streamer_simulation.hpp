#pragma once
// What `streamer_sim` runs: a Streamer whose vehicle API is a real TCP port, and an in-process
// simulated operator — a PlayerCore with a scripted gamepad and self-echo — behind a fake com
// channel (World with one vehicle and no in-process vehicle client). Real time on an
// AsioExecutor. Tests build it directly; the executable adds the command line and signals.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ocp/asio/executor.hpp"
#include "ocp/com_channel.hpp"
#include "sim_app/latency_window.hpp"
#include "ocp/log.hpp"
#include "sim_app/plugin_params.hpp"
#include "world/world.hpp"
#include "sim_app/gamepad_script.hpp"
#include "sim_app/pair_rejection_notes.hpp"
#include "sim_app/simulated_world_options.hpp"
#include "sim_app/tcp_front.hpp"
#include "sim_app/udp_com.hpp"

namespace ocp {

struct StreamerSimOptions : sim_app::SimulatedWorldOptions {   // tcp_port is the vehicle API's
  std::string vehicle = "vehicle";
  // What a busy :4000 tells the user to change: the option of the program that embeds this.
  std::string program = "streamer_sim";
  std::string port_option = "--plugin-param tcp_port N";
  double operator_frame_rate_hz = 100.0;
  Micros operator_phase{0};              // the operator's frames this long after the control ticks
  // --com-listen: the operator is a real Player (player_sim on another host) over UDP at this
  // address, instead of the simulated one; the link's to_player impairments still apply here.
  std::optional<boost::asio::ip::udp::endpoint> com_listen;
  com::ComKey com_key;                   // empty: --com-insecure
};

class StreamerSimulation {
 public:
  StreamerSimulation(AsioExecutor& executor, StreamerSimOptions options, LogSink sink);
  ~StreamerSimulation();
  StreamerSimulation(const StreamerSimulation&) = delete;
  StreamerSimulation& operator=(const StreamerSimulation&) = delete;

  // Listens, then starts the world (so a busy port fails before anything runs). Errors: the
  // port in use (TcpServer::listen), or a configuration error from World::start.
  [[nodiscard]] Status start();
  void stop();

  std::uint16_t port() const { return front_->port(); }
  std::string address() const { return front_->address(); }
  World& world() { return world_; }
  StreamerCore& streamer() { return world_.streamer(options_.vehicle); }
  PlayerCore& player() { return world_.player(); }
  sim_app::TcpFront& front() { return *front_; }
  sim_app::UdpComEndpoint* com() { return com_.get(); }   // nullptr without --com-listen

  // The once-per-second status line; rates are per second since the previous call, latency
  // min/avg/max over the samples since then (every control tick while a vehicle is connected);
  // while returned pairs are rejected, why (PairRejected's hint).
  std::string status_line();

 private:
  void attach_remote_operator();

  AsioExecutor& executor_;
  StreamerSimOptions options_;
  Logger logger_;
  World world_;
  sim_app::PairRejectionNotes pair_notes_;   // why the loop does not close, for the status line
  std::unique_ptr<sim_app::TcpFront> front_;
  std::unique_ptr<sim_app::UdpComEndpoint> com_;
  PeriodicTimer latency_sampler_;
  LatencyWindow latency_window_;
  struct Previous {
    SimTime time{0};
    std::uint64_t control_frames_sent = 0;
    std::uint64_t vehicle_responses_received = 0;
    std::uint64_t operator_messages_received = 0;
  } previous_;
};

}  // namespace ocp
