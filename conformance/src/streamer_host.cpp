#include "conformance/streamer_host.hpp"

#include <system_error>
#include <thread>
#include <utility>

namespace ocp::conformance {

StreamerHost::StreamerHost(LogSink sink)
    : executor_(io_), sink_(std::move(sink)),
      server_(io_, [this](std::shared_ptr<ByteStream> stream) { on_client_stream(std::move(stream)); }) {}

StreamerHost::StreamerHost(const vtime::ControllerOptions& virtual_time, LogSink sink) : StreamerHost(std::move(sink)) {
  virtual_ = std::make_unique<Virtual>();
  virtual_->controller = std::make_unique<vtime::Controller>(virtual_->executor, virtual_time);
}

StreamerHost::~StreamerHost() {
  stop_streamer();
  server_.stop();
}

void StreamerHost::on_client_stream(std::shared_ptr<ByteStream> stream) {
  // Between two cases there is no Streamer: the client is turned away and retries.
  if (world_ && operator_side_) {
    world_->player().accept_client_connection(std::move(stream));
  } else if (world_) {
    world_->accept_vehicle_connection(host_vehicle_name, std::move(stream));
  } else {
    stream->close();
  }
}

Status StreamerHost::listen(std::uint16_t port) {
  if (virtual_) {
    try {
      virtual_->listener =
          virtual_->controller->listen(port, [this](std::shared_ptr<ByteStream> stream) { on_client_stream(std::move(stream)); });
    } catch (const vtime::VirtualTimeError& error) {
      return Error{std::make_error_code(std::errc::io_error), error.what()};
    }
    port_ = virtual_->controller->port(virtual_->listener);
    return Ok{};
  }
  if (auto status = server_.listen(TcpServerOptions{port, false}); !status) return status;
  port_ = server_.port();
  return Ok{};
}

Status StreamerHost::start_streamer(const StreamerSetup& setup) {
  stop_streamer();
  WorldConfig config;
  config.seed = 1;
  config.player.name = "operator";
  config.player.frame_rate_hz = 100.0;
  std::vector<HostedVehicle> hosted = setup.fleet;
  if (hosted.empty() || !setup.operator_side) hosted = {HostedVehicle{host_vehicle_name, false}};
  config.player.fleet = hosted.size() > 1;
  for (const HostedVehicle& h : hosted) {
    VehicleSpec vehicle;
    vehicle.name = h.name;
    vehicle.monitor = h.monitor;
    vehicle.streamer.ack_time_offset = setup.ack_time_offset;
    vehicle.streamer.vehicle_write_queue_limit_bytes = setup.write_queue_limit_bytes;
    // Vehicle API: the client under test is the vehicle. Operator API: the reference client is.
    vehicle.in_process_client = setup.operator_side;
    config.vehicles.push_back(std::move(vehicle));
  }
  auto world = std::make_unique<World>(clock(), std::move(config), sink_);
  if (auto status = world->start(); !status) return status;
  // Before the io_context runs again, so no client can connect to an unpaused Streamer.
  for (const HostedVehicle& h : hosted) world->streamer(h.name).set_control_output_paused(setup.control_paused);
  world_ = std::move(world);
  vehicles_ = std::move(hosted);
  operator_side_ = setup.operator_side;
  return Ok{};
}

void StreamerHost::stop_streamer() {
  if (!world_) return;
  world_->stop();
  world_.reset();
}

Status StreamerHost::restart(const StreamerSetup& setup) {
  stop_streamer();
  if (virtual_) {   // closed now, listening again at this same virtual instant (before any client can run)
    virtual_->controller->close_listener_for(virtual_->listener, Micros{0});
    return start_streamer(setup);
  }
  const std::uint16_t port = port_;
  server_.stop();
  // The closed sockets' handlers run on the io_context; until they have, the kernel may still
  // see the old listener. Retry the bind for a bounded time.
  Status bound = listen(port);
  for (int attempt = 0; !bound && attempt < 100; ++attempt) {
    run_for(std::chrono::milliseconds(20));
    bound = listen(port);
  }
  if (!bound) return bound;
  return start_streamer(setup);
}

StreamerCore& StreamerHost::streamer() { return world_->streamer(host_vehicle_name); }
StreamerCore& StreamerHost::streamer(std::string_view vehicle) { return world_->streamer(vehicle); }
std::vector<HostedVehicle> StreamerHost::vehicles() const { return world_ ? vehicles_ : std::vector<HostedVehicle>{}; }
PlayerCore& StreamerHost::player() { return world_->player(); }

bool StreamerHost::client_connected() {
  if (!world_) return false;
  return operator_side_ ? world_->player().client_connected() : streamer().vehicle_connected();
}

std::uint64_t StreamerHost::client_connections_accepted() {
  if (!world_) return 0;
  return operator_side_ ? world_->player().stats().client_connections_accepted
                        : streamer().stats().connections_accepted;
}

EventBus& StreamerHost::client_events() { return operator_side_ ? world_->player().events() : streamer().events(); }

bool StreamerHost::run_until(const std::function<bool()>& done, std::chrono::milliseconds timeout) {
  if (virtual_) return run_until_virtual(done, timeout);
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!done()) {
    if (stop_asked()) throw RunInterrupted();
    const auto now = std::chrono::steady_clock::now();
    if (now >= deadline) return false;
    if (io_.stopped()) io_.restart();
    const auto slice = std::min<std::chrono::steady_clock::duration>(deadline - now, std::chrono::milliseconds(5));
    if (io_.run_one_for(slice) == 0 && io_.stopped()) {
      // No work at all: nothing changes until the client does something.
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }
  return true;
}

// Virtual time: the Controller runs the World and the client to `timeout` from now, and looks at
// `done` between instants (after every exchange of the instant), so it stops at the first
// instant where it holds. A client that cannot live in virtual time throws VirtualTimeError.
bool StreamerHost::run_until_virtual(const std::function<bool()>& done, std::chrono::milliseconds timeout) {
  const SimTime end = virtual_->executor.now() + std::chrono::duration_cast<Micros>(timeout);
  while (!done()) {
    if (stop_asked()) throw RunInterrupted();
    if (virtual_->executor.now() >= end) return false;
    virtual_->controller->run_until(end, [&] { return done() || stop_asked(); });
  }
  return true;
}

void StreamerHost::run_for(std::chrono::milliseconds duration) {
  if (virtual_) {
    const SimTime end = virtual_->executor.now() + std::chrono::duration_cast<Micros>(duration);
    (void)run_until_virtual([&] { return virtual_->executor.now() >= end; }, duration);
    return;
  }
  const auto deadline = std::chrono::steady_clock::now() + duration;
  run_until([&] { return std::chrono::steady_clock::now() >= deadline; }, duration + std::chrono::milliseconds(1));
}

}  // namespace ocp::conformance
