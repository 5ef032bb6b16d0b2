#include "player_app/player_simulation.hpp"

#include <fmt/format.h>

#include <utility>

#include "sim_app/port_hint.hpp"
#include "sim_app/console.hpp"

namespace ocp {

namespace {

std::string format_identifiers(const std::vector<std::string>& identifiers) {
  if (identifiers.empty()) return "[]";
  std::string text;
  for (const auto& identifier : identifiers) text += (text.empty() ? "" : ",") + identifier;
  return "[" + text + "]";
}

WorldConfig make_world_config(const PlayerSimOptions& options) {
  WorldConfig config;
  config.seed = options.seed;
  config.player.name = "player";
  config.player.frame_rate_hz = options.frame_rate_hz;
  config.player.fleet = options.vehicles.size() > 1;
  for (const auto& name : options.vehicles) {
    VehicleSpec vehicle;
    vehicle.name = name;
    vehicle.streamer.latency_limit = options.plugin_params.latency_limit;
    vehicle.streamer.ack_time_offset = options.ack_time_offset;
    if (!options.cameras.empty()) vehicle.streamer.cameras = options.cameras;
    vehicle.to_streamer = options.to_streamer();
    vehicle.to_player = options.to_player();
    // The reference vehicle client over an in-memory pipe, unless an external one connects
    // over TCP (--vehicle-tcp).
    vehicle.in_process_client = !options.vehicle_tcp_ports.contains(name) && !options.udp_vehicles.contains(name);
    config.vehicles.push_back(std::move(vehicle));
  }
  return config;
}

}  // namespace

PlayerSimulation::PlayerSimulation(AsioExecutor& executor, PlayerSimOptions options, LogSink sink)
    : executor_(executor),
      options_(std::move(options)),
      logger_(executor, "player_sim", sink),
      world_(executor, make_world_config(options_), sink),
      front_(sim_app::operator_api_front(executor, world_, Logger(executor, "player:tcp", sink))),
      latency_sampler_(executor, Micros{10'000}, [this](SimTime) {
        for (const auto& name : options_.vehicles) {
          const StreamerCore& streamer = world_.streamer(name);
          if (const auto latency = streamer.latency_ms(); latency && streamer.vehicle_connected()) {
            latency_windows_[name].add(*latency);
          }
        }
      }) {
  for (const auto& [name, port] : options_.vehicle_tcp_ports) {
    vehicle_fronts_[name] = sim_app::vehicle_api_front(executor, world_, name, Logger(executor, "streamer:" + name + ":tcp", sink));
  }
  for (const auto& [name, peer] : options_.udp_vehicles) {
    coms_[name] = std::make_unique<sim_app::UdpComEndpoint>(executor, false, options_.com_key,
                                                            Logger(executor, "player:" + name + ":com", sink));
  }
  if (options_.webview) {
    WebviewOptions webview = *options_.webview;
    webview.allow_remote = options_.plugin_params.ocp_tcp_allow_remote;
    webview_ = std::make_unique<WebviewServer>(executor, std::move(webview), Logger(executor, "player:webview", sink));
  }
}

std::uint16_t PlayerSimulation::vehicle_port(const std::string& vehicle) const {
  const auto found = vehicle_fronts_.find(vehicle);
  return found == vehicle_fronts_.end() ? 0 : found->second->port();
}

PlayerSimulation::~PlayerSimulation() { stop(); }

sim_app::UdpComEndpoint* PlayerSimulation::com(const std::string& vehicle) {
  const auto found = coms_.find(vehicle);
  return found == coms_.end() ? nullptr : found->second.get();
}

// The Streamer is across the network: what the Player sends to it goes through the link's
// to_streamer direction (impairments at the sender) into the socket, and what arrives goes
// straight to the Player. The local stand-in Streamer is stopped and delivers nothing.
void PlayerSimulation::attach_remote_streamer(const std::string& vehicle) {
  ComChannel& link = world_.link(vehicle);
  sim_app::UdpComEndpoint& com = *coms_.at(vehicle);
  world_.streamer(vehicle).stop();
  link.to_player().set_receiver([](LinkMessage&&) {});
  link.to_streamer().set_receiver(forward_to(com));
  com.set_receiver([this, vehicle](LinkMessage&& message) { world_.player().handle_link_message(vehicle, std::move(message)); });
}

Status PlayerSimulation::start() {
  const TcpServerOptions listen_options{options_.plugin_params.ocp_player_tcp_port,
                                        options_.plugin_params.ocp_tcp_allow_remote};
  if (auto status = front_->listen(listen_options); !status) {
    return sim_app::with_port_hint(status, "player_sim", "--plugin-param ocp_player_tcp_port N");
  }
  for (const auto& [name, front] : vehicle_fronts_) {
    const TcpServerOptions vehicle_options{options_.vehicle_tcp_ports.at(name), options_.plugin_params.ocp_tcp_allow_remote};
    if (auto status = front->listen(vehicle_options); !status) {
      stop();
      return sim_app::with_port_hint(status, "player_sim", "--vehicle-tcp " + name + "=PORT");
    }
  }
  if (webview_) {
    if (auto status = webview_->listen(); !status) {
      stop();
      return sim_app::with_port_hint(status, "player_sim", "--webview-port N (0: any free port), or --no-webview");
    }
  }
  for (const auto& [name, com] : coms_) {
    if (auto status = com->connect(options_.udp_vehicles.at(name)); !status) {
      stop();
      return status;
    }
  }
  if (auto status = world_.start(); !status) {
    stop();
    return status;
  }
  for (const auto& [name, com] : coms_) attach_remote_streamer(name);
  // The Streamers exist once the world started.
  for (const auto& name : options_.vehicles) pair_notes_.follow(world_.streamer(name).events());
  if (webview_) {
    webview_->attach(world_.player());
    webview_->show_loop_notes(&pair_notes_);
  }
  sim_app::apply_gamepad_script(world_.player().gamepad(), options_.gamepad, executor_.now());
  std::string names;
  for (const auto& name : options_.vehicles) {
    names += (names.empty() ? "" : ", ") + name;
    if (const auto front = vehicle_fronts_.find(name); front != vehicle_fronts_.end()) {
      names += " (external vehicle client on " + front->second->address() + ")";
    }
    if (coms_.contains(name)) names += " (a real Streamer over UDP)";
  }
  logger_.info("simulated vehicles: {} ({}); gamepad '{}', link delay {} ms, jitter ±{} ms, loss {}",
               names, options_.vehicles.size() > 1 ? "fleet" : "single vehicle",
               options_.gamepad.description, to_whole_ms(options_.link.delay),
               to_whole_ms(options_.link.jitter), options_.link.loss_probability);
  previous_ = Previous{executor_.now(), 0, 0};
  latency_sampler_.start(executor_.now() + latency_sampler_.period());
  return Ok{};
}

void PlayerSimulation::stop() {
  for (auto& [name, com] : coms_) com->stop();
  if (webview_) webview_->stop();
  for (auto& [name, front] : vehicle_fronts_) front->stop();
  latency_sampler_.stop();
  front_->stop();
  if (world_.running()) world_.stop();
}

std::string PlayerSimulation::status_line() {
  const PlayerCore& core = player();
  const PlayerStats& stats = core.stats();
  const SimTime now = executor_.now();
  const Micros elapsed = now - previous_.time;
  std::string client = "none";
  if (core.client_connected()) client = "connected";
  if (core.tcp_lock_without_client()) {
    client += fmt::format(" ({})", tcp_lock_without_client_text);   // SPEC §4.3: said every second
  } else if (const auto source = core.locked_source()) {
    client += fmt::format(" (source {}{})", client_source_name(*source),
                          core.client_data_stopped() ? ", client data STOPPED by a source conflict" : "");
  }
  // SPEC §2 keeps a VehicleOcpShared over 16 KiB off the wire, so the client gets nothing:
  // said here, every second, not only in the one warning of the episode.
  if (const auto& too_large = core.client_frame_too_large()) client += " | " + describe(*too_large);
  std::string line = fmt::format(
      "status: operator client {} | feedback out {:.0f}/s ({} total) | client msgs in {:.0f}/s ({} total)",
      client, sim_app::per_second(stats.client_frames_sent, previous_.client_frames_sent, elapsed),
      stats.client_frames_sent,
      sim_app::per_second(stats.client_messages_received, previous_.client_messages_received, elapsed),
      stats.client_messages_received);
  for (const auto& name : options_.vehicles) {
    const StreamerCore& streamer = world_.streamer(name);
    LatencyWindow& latency = latency_windows_[name];
    const auto* com = coms_.contains(name) ? coms_.at(name).get() : nullptr;
    std::string client_view = "nothing sent yet";
    const auto& feedback = core.last_shared().vehicle_feedback;
    if (const auto found = feedback.find(name); found != feedback.end()) {
      client_view = fmt::format("receiver_fault {}, sender_fault {}", format_identifiers(found->second.receiver_fault),
                                format_identifiers(found->second.sender_fault));
    }
    if (com) {
      line += fmt::format(" | {}: {}; operator client sees: {}", name, com->describe(), client_view);
    } else {
      line += fmt::format(" | {}: simulated Streamer: latency {}, faults {}; operator client sees: {}", name,
                          streamer.vehicle_connected() ? latency.format() : std::string("n/a (no loop running)"),
                          sim_app::format_faults(streamer.faults()), client_view);
      if (const std::string* why = pair_notes_.hint(name)) line += "; loop not closed: " + *why;
    }
    latency.reset();
  }
  previous_ = Previous{now, stats.client_frames_sent, stats.client_messages_received};
  return line;
}

}  // namespace ocp
