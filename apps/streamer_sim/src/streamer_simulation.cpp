#include "streamer_app/streamer_simulation.hpp"

#include <fmt/format.h>

#include <utility>

#include "sim_app/console.hpp"
#include "sim_app/port_hint.hpp"

namespace ocp {

namespace {

WorldConfig make_world_config(const StreamerSimOptions& options) {
  WorldConfig config;
  config.seed = options.seed;
  config.player.name = "operator";
  config.player.frame_rate_hz = options.operator_frame_rate_hz;
  config.player_phase = options.operator_phase;
  VehicleSpec vehicle;
  vehicle.name = options.vehicle;
  vehicle.streamer.latency_limit = options.plugin_params.latency_limit;
  vehicle.streamer.ack_time_offset = options.ack_time_offset;
  if (!options.cameras.empty()) vehicle.streamer.cameras = options.cameras;
  vehicle.to_streamer = options.to_streamer();
  vehicle.to_player = options.to_player();
  vehicle.in_process_client = false;   // the vehicle client is whoever connects over TCP
  config.vehicles.push_back(std::move(vehicle));
  return config;
}

}  // namespace

StreamerSimulation::StreamerSimulation(AsioExecutor& executor, StreamerSimOptions options, LogSink sink)
    : executor_(executor),
      options_(std::move(options)),
      logger_(executor, "streamer_sim", sink),
      world_(executor, make_world_config(options_), sink),
      front_(sim_app::vehicle_api_front(executor, world_, options_.vehicle,
                                        Logger(executor, "streamer:" + options_.vehicle + ":tcp", sink))),
      latency_sampler_(executor, Micros{10'000}, [this](SimTime) {
        const StreamerCore& core = streamer();
        if (const auto latency = core.latency_ms(); latency && core.vehicle_connected()) latency_window_.add(*latency);
      }) {
  if (options_.com_listen) {
    com_ = std::make_unique<sim_app::UdpComEndpoint>(executor, true, options_.com_key,
                                                     Logger(executor, "streamer:" + options_.vehicle + ":com", sink));
  }
}

StreamerSimulation::~StreamerSimulation() { stop(); }

Status StreamerSimulation::start() {
  const TcpServerOptions listen_options{options_.plugin_params.tcp_port,
                                        options_.plugin_params.ocp_tcp_allow_remote};
  if (auto status = front_->listen(listen_options); !status) {
    return sim_app::with_port_hint(status, options_.program, options_.port_option);
  }
  if (com_) {
    if (auto status = com_->listen(*options_.com_listen); !status) {
      front_->stop();
      return sim_app::with_port_hint(status, "streamer_sim", "--com-listen ADDR:PORT");
    }
  }
  if (auto status = world_.start(); !status) {
    front_->stop();
    if (com_) com_->stop();
    return status;
  }
  pair_notes_.follow(streamer().events());   // the Streamer exists once the world started
  if (com_) attach_remote_operator();
  sim_app::apply_gamepad_script(world_.player().gamepad(), options_.gamepad, executor_.now());
  if (com_) {
    logger_.info("operator: a Player over UDP (player_sim --vehicle {}=udp://HOST:{}), link impairments added here: "
                 "delay {} ms, jitter ±{} ms, loss {}{}",
                 options_.vehicle, com_->local_port(), to_whole_ms(options_.link.delay), to_whole_ms(options_.link.jitter),
                 options_.link.loss_probability, options_.com_key.empty() ? "; INSECURE (no key)" : "");
  } else {
    logger_.info("simulated operator: gamepad '{}', link delay {} ms, jitter ±{} ms, loss {}, latency_limit {} ms, "
                 "ack_time offset {}",
                 options_.gamepad.description, to_whole_ms(options_.link.delay),
                 to_whole_ms(options_.link.jitter), options_.link.loss_probability,
                 options_.plugin_params.latency_limit.count(), options_.ack_time_offset);
  }
  latency_sampler_.start(executor_.now() + latency_sampler_.period());
  previous_ = Previous{executor_.now(), 0, 0, 0};
  return Ok{};
}

// The Player is across the network: what the Streamer sends goes through its to_player
// direction (impairments at the sender) into the socket, and what arrives goes straight to the
// Streamer. The simulated operator is stopped, and its direction delivers nothing.
void StreamerSimulation::attach_remote_operator() {
  ComChannel& link = world_.link(options_.vehicle);
  world_.player().stop();
  link.to_streamer().set_receiver([](LinkMessage&&) {});
  link.to_player().set_receiver(forward_to(*com_));
  com_->set_receiver([this](LinkMessage&& message) { streamer().handle_link_message(std::move(message)); });
}

void StreamerSimulation::stop() {
  if (com_) com_->stop();
  latency_sampler_.stop();
  front_->stop();
  if (world_.running()) world_.stop();
}

std::string StreamerSimulation::status_line() {
  const StreamerCore& core = streamer();
  const StreamerStats& stats = core.stats();
  const SimTime now = executor_.now();
  const Micros elapsed = now - previous_.time;
  const std::string vehicle = core.vehicle_connected() ? core.vehicle_peer() : std::string("none");
  // Without a vehicle client no loop runs: the last measured latency would be stale.
  const std::string latency =
      core.vehicle_connected() ? latency_window_.format() : std::string("n/a (no loop running)");
  latency_window_.reset();
  std::string line = fmt::format(
      "status: vehicle client {} | latency {} | faults {} | control out {:.0f}/s ({} total) | "
      "responses in {:.0f}/s ({} total) | operator msgs in {:.0f}/s",
      vehicle, latency, sim_app::format_faults(core.faults()),
      sim_app::per_second(stats.control_frames_sent, previous_.control_frames_sent, elapsed),
      stats.control_frames_sent,
      sim_app::per_second(stats.vehicle_responses_received, previous_.vehicle_responses_received, elapsed),
      stats.vehicle_responses_received,
      sim_app::per_second(stats.operator_messages_received, previous_.operator_messages_received, elapsed));
  if (const std::string* why = pair_notes_.hint(options_.vehicle)) line += " | loop not closed: " + *why;
  if (com_) line += " | " + com_->describe();
  previous_ = Previous{now, stats.control_frames_sent, stats.vehicle_responses_received,
                       stats.operator_messages_received};
  return line;
}

}  // namespace ocp
