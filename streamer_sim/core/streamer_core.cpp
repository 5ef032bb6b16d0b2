#include "streamer/streamer_core.hpp"

#include <algorithm>

#include "streamer_impl.hpp"

namespace ocp {

StreamerCore::Impl::Impl(Executor& executor_in, StreamerConfig config_in, Logger logger_in)
    : executor(executor_in),
      config(std::move(config_in)),
      logger(std::move(logger_in)),
      faults(logger, [this](FaultId id, bool active) { publish_fault(id, active); }),
      latency_loop(config.mac_key ? *config.mac_key : random_mac_key(), config.ack_time_offset),
      cameras(executor, config.cameras, logger),
      frame_loop(executor, config.frame_rate_hz, [this](Micros took) { on_frame_iteration(took); }),
      control_timer(executor, config.control_period,
                    [this](SimTime deadline) { on_control_tick(deadline); }) {}

void StreamerCore::Impl::start(SimTime t0) {
  if (started) return;
  started = true;
  start_time = t0;
  last_operator_arrival = start_time;
  latency_loop.start(start_time);
  logger.info("streamer {} started: control every {} us, frame loop {} Hz, {} camera(s)",
              config.name, config.control_period.count(), config.frame_rate_hz,
              config.cameras.size());
  faults.set(FaultId::VehicleNoResponse, vehicle_connection == nullptr);
  cameras.start(start_time, [this](VideoFrame&& frame) { send_video_frame(std::move(frame)); });
  if (!frame_loop.start(start_time)) {
    logger.error("frame_rate_hz {} is not a positive rate; no feedback will be sent",
                 config.frame_rate_hz);
  }
  if (config.control_period <= Micros{0}) {
    logger.error("control_period must be positive; no control messages will be sent");
  } else if (control_ticker != nullptr && control_ticker->period() == config.control_period) {
    ticker_member = control_ticker->add([this](SimTime deadline) { on_control_tick(deadline); });
  } else {
    control_timer.start(start_time);
  }
}

void StreamerCore::Impl::stop() {
  if (!started) return;
  started = false;
  control_timer.stop();
  if (control_ticker != nullptr) control_ticker->remove(ticker_member);
  ticker_member = {};
  frame_loop.stop();
  cameras.stop();
  if (vehicle_connection) vehicle_connection->close(CloseReason{LocalError::shut_down, "streamer stopped"});
  logger.info("streamer {} stopped", config.name);
}

void StreamerCore::Impl::publish_fault(FaultId id, bool active) {
  if (!events.active()) return;
  events.publish(Event{executor.now(), component(),
                       FaultEvent{FaultSide::vehicle, id, active, config.name}});
}

void StreamerCore::Impl::publish_latency_sample(SimTime deadline, SimTime now) {
  if (!events.active()) return;
  LatencySample sample;
  sample.latency_ms = latency_loop.latency_ms(now);
  sample.pair_age = latency_loop.newest_pair_age(now);
  sample.tick_lateness = now - deadline;
  sample.control_sent = control_sent;
  events.publish(Event{now, component(), sample});
}

StreamerCore::StreamerCore(Executor& executor, StreamerConfig config, Logger logger)
    : impl_(std::make_unique<Impl>(executor, std::move(config), std::move(logger))) {}

StreamerCore::~StreamerCore() {
  impl_->stop();
}

void StreamerCore::start() { impl_->start(impl_->executor.now()); }
void StreamerCore::start(SimTime t0) { impl_->start(std::min(t0, impl_->executor.now())); }
void StreamerCore::stop() { impl_->stop(); }
void StreamerCore::set_link(Link* to_player) { impl_->to_player = to_player; }
void StreamerCore::use_control_ticker(ControlTicker* ticker) { impl_->control_ticker = ticker; }

void StreamerCore::handle_link_message(LinkMessage&& message) {
  impl_->handle_link_message(std::move(message));
}

void StreamerCore::accept_vehicle_connection(std::shared_ptr<ByteStream> stream) {
  impl_->accept_vehicle(std::move(stream));
}

void StreamerCore::set_camera_stalled(std::string_view camera, bool stalled) {
  if (!impl_->cameras.set_stalled(camera, stalled)) {
    impl_->logger.warn("set_camera_stalled: no camera named '{}'", camera);
  }
}

void StreamerCore::inject_frame_loop_stall(Micros duration) {
  impl_->logger.info("frame loop: injecting a stall of {} us into the next iteration",
                      duration.count());
  impl_->frame_loop.inject_stall(duration);
}

void StreamerCore::set_control_thread_stalled(bool stalled) {
  impl_->control_thread_stalled = stalled;
  impl_->logger.info("control thread {}", stalled ? "stalled" : "resumed");
  if (!stalled) impl_->drain_inbox();
  impl_->evaluate_inbox_fault();
}

void StreamerCore::set_control_output_paused(bool paused) { impl_->control_output_paused = paused; }
bool StreamerCore::control_output_paused() const { return impl_->control_output_paused; }

Status StreamerCore::write_raw_to_vehicle(std::string bytes, std::vector<std::size_t> cuts, Micros gap) {
  return impl_->write_raw_to_vehicle(std::move(bytes), std::move(cuts), gap);
}

void StreamerCore::close_vehicle_connection() {
  if (impl_->vehicle_connection) {
    impl_->vehicle_connection->close(CloseReason{LocalError::shut_down, "closed by the server on request"});
  }
}

EventBus& StreamerCore::events() { return impl_->events; }

const FaultSet& StreamerCore::faults() const { return impl_->faults.faults(); }

std::optional<std::uint64_t> StreamerCore::latency_ms() const {
  return impl_->latency_loop.latency_ms(impl_->executor.now());
}

bool StreamerCore::vehicle_connected() const { return impl_->vehicle_connection != nullptr; }

std::string StreamerCore::vehicle_peer() const {
  return impl_->vehicle_connection ? impl_->vehicle_connection->peer() : std::string();
}

const StreamerStats& StreamerCore::stats() const { return impl_->stats; }
const StreamerConfig& StreamerCore::config() const { return impl_->config; }
std::optional<AckPair> StreamerCore::latest_echoed_pair() const { return impl_->echoed_pair; }
std::optional<Controller> StreamerCore::last_sent_controller() const {
  return impl_->last_sent_controller;
}

}  // namespace ocp
