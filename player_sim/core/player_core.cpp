// PlayerCore: lifecycle, vehicles, inputs from the com channel, getters.
#include "player/player_core.hpp"

#include <cmath>
#include <utility>
#include <variant>

#include <fmt/format.h>

#include "player_impl.hpp"

namespace ocp {

std::string describe(const ClientFrameTooLarge& too_large) {
  return fmt::format("VehicleOcpShared too large: {} B > {} B, not sent to the client ({} frames)",
                     too_large.bytes, too_large.limit, too_large.frames);
}

Micros player_frame_period(const PlayerConfig& config) {
  double rate_hz = config.frame_rate_hz;
  if (!std::isfinite(rate_hz) || rate_hz <= 0.0) rate_hz = max_player_frame_rate_hz;
  if (rate_hz > max_player_frame_rate_hz) rate_hz = max_player_frame_rate_hz;
  return Micros{static_cast<std::int64_t>(std::llround(1e6 / rate_hz))};
}

PlayerCore::Impl::Impl(Executor& executor_in, PlayerConfig config_in, Logger logger_in)
    : executor(executor_in),
      config(std::move(config_in)),
      logger(std::move(logger_in)),
      frame_period(player_frame_period(config)),
      frame_timer(executor, frame_period, [this](SimTime) { on_frame(); }),
      ping_timer(executor, config.ping_period, [this](SimTime) { on_ping(); }) {}

PlayerCore::PlayerCore(Executor& executor, PlayerConfig config, Logger logger)
    : impl_(std::make_unique<Impl>(executor, std::move(config), std::move(logger))) {
  const PlayerConfig& used = impl_->config;
  if (!std::isfinite(used.frame_rate_hz) || used.frame_rate_hz <= 0.0) {
    impl_->logger.error("frame_rate_hz {} is not a positive rate; using {} Hz", used.frame_rate_hz,
                        max_player_frame_rate_hz);
  } else if (used.frame_rate_hz > max_player_frame_rate_hz) {
    impl_->logger.warn("frame_rate_hz {} capped at {} Hz", used.frame_rate_hz, max_player_frame_rate_hz);
  }
}

PlayerCore::~PlayerCore() { stop(); }

void PlayerCore::start() {
  Impl& self = *impl_;
  if (self.running) return;
  self.running = true;
  self.started_at = self.executor.now();
  self.frame_timer.start(self.started_at);
  if (self.config.ping_period.count() > 0) self.ping_timer.start(self.started_at);
  self.logger.info("started: {} vehicle(s), frame period {} us", self.vehicles.size(),
                   self.frame_period.count());
}

void PlayerCore::stop() {
  Impl& self = *impl_;
  if (!self.running && !self.client) return;
  self.running = false;
  self.frame_timer.stop();
  self.ping_timer.stop();
  if (self.client) {
    auto client = self.client;
    client->close(CloseReason{LocalError::shut_down, "player stopped"});
  }
}

bool PlayerCore::running() const { return impl_->running; }

Status PlayerCore::add_vehicle(const std::string& name, Link* to_streamer, bool monitor) {
  Impl& self = *impl_;
  auto configuration_error = [](std::string detail) {
    return Error{std::make_error_code(std::errc::invalid_argument), std::move(detail)};
  };
  if (name.empty()) return configuration_error("vehicle name must not be empty");
  if (self.vehicles.contains(name)) {
    return configuration_error("vehicle '" + name + "' is already linked");
  }
  if (!self.config.fleet && !self.vehicles.empty()) {
    return configuration_error("cannot link vehicle '" + name + "': without a fleet configuration "
                               "the Player supports exactly one Streamer (already linked: '" +
                               self.vehicles.begin()->first + "')");
  }
  if (to_streamer == nullptr && !monitor) {
    return configuration_error("vehicle '" + name + "' needs a link towards its Streamer");
  }
  VehicleLink link;
  link.name = name;
  link.to_streamer = to_streamer;
  link.monitor = monitor;
  link.linked_at = self.executor.now();
  self.vehicles.emplace(name, std::move(link));
  self.logger.info("linked vehicle '{}'{}", name, monitor ? " (monitor)" : "");
  return Ok{};
}

Status PlayerCore::remove_vehicle(const std::string& name) {
  Impl& self = *impl_;
  auto configuration_error = [](std::string detail) {
    return Error{std::make_error_code(std::errc::invalid_argument), std::move(detail)};
  };
  if (self.running) return configuration_error("cannot unlink vehicle '" + name + "' while the Player runs");
  if (self.vehicles.erase(name) == 0) return configuration_error("vehicle '" + name + "' is not linked");
  // A Player started and stopped before has an entry for it: refresh_shared walks both in step.
  self.last_shared.vehicle_feedback.erase(name);
  self.logger.info("unlinked vehicle '{}'", name);
  return Ok{};
}

void PlayerCore::accept_client_connection(std::shared_ptr<ByteStream> stream) {
  impl_->accept_client(std::move(stream));
}

void PlayerCore::handle_client_data(ClientSource source, const ClientOcpShared& data) {
  impl_->on_client_data(source, data);
}

void PlayerCore::select_vehicle(std::optional<std::string> vehicle) {
  Impl& self = *impl_;
  if (vehicle && !self.vehicles.contains(*vehicle)) {
    self.logger.warn("selected vehicle '{}' is not linked; no vehicle is active", *vehicle);
  }
  self.selected_vehicle = std::move(vehicle);
}

void PlayerCore::add_shared_listener(SharedListener listener) {
  impl_->shared_listeners.push_back(std::move(listener));
}

Gamepad& PlayerCore::gamepad() { return impl_->gamepad; }
const Gamepad& PlayerCore::gamepad() const { return impl_->gamepad; }
const PlayerConfig& PlayerCore::config() const { return impl_->config; }

std::vector<std::string> PlayerCore::vehicles() const {
  std::vector<std::string> names;
  for (const auto& [name, link] : impl_->vehicles) names.push_back(name);
  return names;
}

FaultSet PlayerCore::sender_faults(const std::string& vehicle) const {
  const auto found = impl_->vehicles.find(vehicle);
  return found == impl_->vehicles.end() ? FaultSet{} : found->second.sender_faults;
}

const VehicleOcpShared& PlayerCore::last_shared() const { return impl_->last_shared; }
std::optional<ClientSource> PlayerCore::locked_source() const { return impl_->source_lock.locked(); }
bool PlayerCore::client_data_stopped() const { return impl_->source_lock.stopped(); }
bool PlayerCore::tcp_lock_without_client() const {
  return impl_->source_lock.locked() == ClientSource::tcp && !impl_->source_lock.stopped() && !impl_->client;
}
std::optional<std::string> PlayerCore::active_vehicle() const { return impl_->resolve_active_vehicle(); }

std::optional<AckPair> PlayerCore::latest_sei(const std::string& vehicle) const {
  const auto found = impl_->vehicles.find(vehicle);
  return found == impl_->vehicles.end() ? std::nullopt : found->second.latest_sei;
}

void PlayerCore::set_client_output_paused(bool paused) { impl_->client_output_paused = paused; }
bool PlayerCore::client_output_paused() const { return impl_->client_output_paused; }

void PlayerCore::close_client_connection() {
  if (!impl_->client) return;
  auto client = impl_->client;   // on_client_closed resets impl_->client during close()
  client->close(CloseReason{LocalError::shut_down, "closed by the Player (conformance test)"});
}

Status PlayerCore::write_raw_to_client(std::string bytes, std::vector<std::size_t> cuts, Micros gap) {
  return impl_->write_raw_to_client(std::move(bytes), std::move(cuts), gap);
}

bool PlayerCore::client_connected() const { return impl_->client && impl_->client->is_open(); }
const std::optional<ClientFrameTooLarge>& PlayerCore::client_frame_too_large() const {
  return impl_->client_too_large;
}
std::size_t PlayerCore::remembered_unknown_names() const {
  return impl_->warned_unknown_entries.size() + impl_->warned_unknown_active.size() +
         impl_->warned_unknown_senders.size();
}
const std::optional<CloseReason>& PlayerCore::last_client_close_reason() const {
  return impl_->last_client_close_reason;
}
EventBus& PlayerCore::events() { return impl_->events; }
const PlayerStats& PlayerCore::stats() const { return impl_->stats; }

}  // namespace ocp
