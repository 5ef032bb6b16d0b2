#include "world/world.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <utility>
#include <variant>

#include "ocp/invariant.hpp"
#include "ocp/pipe.hpp"
#include "streamer/control_ticker.hpp"
#include "link_handover.hpp"
#include "world/seeds.hpp"
#include "world/stream_tap.hpp"

namespace ocp {

struct World::Vehicle {
  VehicleSpec spec;
  const StreamerThread* thread = nullptr;   // nullptr: the World's executor
  std::unique_ptr<ComChannel> link;
  std::unique_ptr<StreamerCore> streamer;
  std::unique_ptr<VehicleClient> client;
  std::unique_ptr<StreamTap> tap;
  std::uint64_t connections = 0;
  Executor::TimerId reconnect_timer = 0;
  VehicleListener listener;        // an external client's listening socket (set_vehicle_listener)
  SimTime listening_again_at{0};   // close_vehicle_connection: the port refuses until then
};

// One per (executor, control period) when control_tick_slots > 0.
struct World::Ticker {
  Ticker(Executor& on, Micros period, std::size_t slots, Micros phase)
      : executor(&on), ticker(on, period, slots, phase) {}
  Executor* executor;
  ControlTicker ticker;
};

World::World(Executor& executor, WorldConfig config, LogSink sink)
    : executor_(executor),
      config_(std::move(config)),
      sink_(std::move(sink)),
      logger_(executor, "world", sink_),
      player_(std::make_unique<PlayerCore>(executor, config_.player,
                                           Logger(executor, config_.player.name, sink_))) {
  player_->events().set_parent(&events_);
}

World::~World() { stop(); }

namespace {

Error configuration_error(std::string detail) {
  return Error{std::make_error_code(std::errc::invalid_argument), std::move(detail)};
}

}  // namespace

// A start that fails leaves the World as it found it (nothing running, nothing built, the
// Player without links) and not started: the caller may remove the cause (the Streamer
// threads are the part it can change) and start again.
Status World::start() {
  if (started_) {
    return configuration_error("world already started");
  }
  if (Status valid = check_vehicle_specs(); !valid) return valid;
  if (Status valid = check_streamer_threads(); !valid) return valid;
  if (Status built = build_vehicles(); !built) return built;
  started_ = true;
  if (!streamer_threads_.empty()) create_link_handovers();
  for (auto& vehicle : vehicles_) wire_link_receivers(*vehicle);
  start_parts();
  return Ok{};
}

Status World::check_vehicle_specs() const {
  if (config_.vehicles.empty()) {
    return configuration_error("a world needs at least one vehicle");
  }
  if (config_.player_phase < Micros{0}) {
    return configuration_error("player_phase must not be negative");
  }
  std::set<std::string, std::less<>> names;
  for (const VehicleSpec& spec : config_.vehicles) {
    if (spec.name.empty()) {
      return configuration_error("a vehicle has an empty name");
    }
    if (!names.insert(spec.name).second) {
      return configuration_error("vehicle name '" + spec.name + "' is used twice");
    }
    if (spec.in_process_client) {
      if (auto problem = validate(spec.client)) {
        return configuration_error("vehicle '" + spec.name + "': client: " + *problem);
      }
    }
  }
  return Ok{};
}

Status World::check_streamer_threads() const {
  if (streamer_threads_.empty()) return Ok{};
  for (const StreamerThread& thread : streamer_threads_) {
    if (thread.executor == nullptr || !thread.post) return configuration_error("a Streamer thread without an executor or a poster");
  }
  if (!post_to_world_) return configuration_error("Streamer threads without a poster to the World's thread");
  for (const VehicleSpec& spec : config_.vehicles) {
    // The in-process client and its pipe run on the World's executor, its Streamer would not.
    if (spec.in_process_client) {
      return configuration_error("vehicle '" + spec.name + "': no in-process client with Streamer threads");
    }
  }
  return Ok{};
}

// Every part is built before any starts, so an error the Player finds (it alone knows its
// fleet rule) leaves nothing running.
Status World::build_vehicles() {
  for (const VehicleSpec& spec : config_.vehicles) {
    std::unique_ptr<Vehicle> vehicle = build_vehicle(spec);
    Status linked = player_->add_vehicle(spec.name, &vehicle->link->to_streamer(), spec.monitor);
    if (!linked) {
      discard_vehicles();
      return linked;
    }
    if (spec.in_process_client) build_in_process_client(*vehicle);
    by_name_.emplace(spec.name, vehicle.get());
    vehicles_.push_back(std::move(vehicle));
  }
  return Ok{};
}

std::unique_ptr<World::Vehicle> World::build_vehicle(const VehicleSpec& spec) {
  auto vehicle = std::make_unique<Vehicle>();
  vehicle->spec = spec;
  if (!streamer_threads_.empty()) {
    // Round robin in configuration order: vehicles_ holds the ones built before this one.
    vehicle->thread = &streamer_threads_[vehicles_.size() % streamer_threads_.size()];
  }
  Executor& streamer_executor = vehicle->thread ? *vehicle->thread->executor : executor_;
  vehicle->link = build_link(spec, streamer_executor);
  vehicle->streamer = build_streamer(spec, streamer_executor, vehicle->link->to_player());
  return vehicle;
}

std::unique_ptr<ComChannel> World::build_link(const VehicleSpec& spec, Executor& streamer_executor) {
  // Seeded by the vehicle's name alone, so adding a vehicle never changes another's draws.
  auto link = std::make_unique<ComChannel>(
      executor_, streamer_executor, derive_seed(config_.seed, "link:" + spec.name), spec.name);
  link->events().set_parent(&events_);
  link->to_streamer().set_impairments(spec.to_streamer);
  link->to_player().set_impairments(spec.to_player);
  return link;
}

std::unique_ptr<StreamerCore> World::build_streamer(const VehicleSpec& spec, Executor& streamer_executor,
                                                    LinkDirection& to_player) {
  StreamerConfig streamer_config = spec.streamer;
  streamer_config.name = spec.name;
  if (config_.deterministic_keys && !streamer_config.mac_key) {
    streamer_config.mac_key = derive_mac_key(config_.seed, spec.name);
  }
  auto streamer = std::make_unique<StreamerCore>(
      streamer_executor, streamer_config, Logger(streamer_executor, "streamer:" + spec.name, sink_));
  streamer->set_link(&to_player);
  if (config_.control_tick_slots > 0 && streamer_config.control_period > Micros{0}) {
    streamer->use_control_ticker(&ticker_for(streamer_executor, streamer_config.control_period));
  }
  streamer->events().set_parent(&events_);
  return streamer;
}

void World::build_in_process_client(Vehicle& vehicle) {
  vehicle.client = std::make_unique<VehicleClient>(
      executor_, vehicle.spec.client, Logger(executor_, "vehicle-client:" + vehicle.spec.name, sink_));
  if (config_.tap_vehicle_streams) {
    vehicle.tap = std::make_unique<StreamTap>(executor_);
  }
}

// The Player holds a raw pointer to each link it was given: take the links back before the
// parts they belong to are destroyed, or its frame loop would send on freed links.
void World::discard_vehicles() {
  for (const auto& vehicle : vehicles_) {
    // The World starts the Player only after this, and every vehicle kept here was linked.
    (void)player_->remove_vehicle(vehicle->spec.name);
  }
  by_name_.clear();
  vehicles_.clear();
  OCP_INVARIANT(by_name_.empty() && vehicles_.empty(), "a discarded fleet leaves no vehicle behind");
}

// One hand-over per Streamer thread and one to the World's thread; messages still in flight
// after stop() are dropped on delivery.
void World::create_link_handovers() {
  auto deliver = [this](HandedMessage&& handed) {
    if (!running_) return;
    if (const auto* to = std::get_if<ToStreamer>(&handed.destination)) {
      to->streamer->handle_link_message(std::move(handed.message));
    } else {
      player_->handle_link_message(*std::get<ToPlayer>(handed.destination).from_vehicle, std::move(handed.message));
    }
  };
  auto overflow = [this](std::string where) {
    return [this, where](std::uint64_t dropped) {
      if (dropped == 0) {
        logger_.warn("link hand-over to {} full ({} messages queued): dropping link messages", where,
                     LinkHandover::default_max_queued);
      } else {
        logger_.warn("link hand-over to {}: {} link messages dropped while it was full", where, dropped);
      }
    };
  };
  for (std::size_t index = 0; index < streamer_threads_.size(); ++index) {
    handovers_.push_back(std::make_unique<LinkHandover>(streamer_threads_[index].post, deliver,
                                                        overflow(fmt::format("Streamer thread {}", index))));
  }
  to_world_ = std::make_unique<LinkHandover>(post_to_world_, deliver, overflow("the Player"));
  OCP_INVARIANT(handovers_.size() == streamer_threads_.size(), "one link hand-over per Streamer thread");
}

// Messages still in flight after stop() are dropped here.
void World::wire_link_receivers(Vehicle& vehicle) {
  StreamerCore* streamer = vehicle.streamer.get();
  const std::string* name = &vehicle.spec.name;
  if (const StreamerThread* thread = vehicle.thread) {
    // Delivered on the sender's thread, handed over to the receiver's.
    LinkHandover* to_streamer = handovers_[static_cast<std::size_t>(thread - streamer_threads_.data())].get();
    vehicle.link->to_streamer().set_receiver([to_streamer, streamer](LinkMessage&& message) {
      to_streamer->push(HandedMessage{ToStreamer{streamer}, std::move(message)});
    });
    vehicle.link->to_player().set_receiver([this, name](LinkMessage&& message) {
      to_world_->push(HandedMessage{ToPlayer{name}, std::move(message)});
    });
    return;
  }
  vehicle.link->to_streamer().set_receiver([this, streamer](LinkMessage&& message) {
    if (running_) streamer->handle_link_message(std::move(message));
  });
  vehicle.link->to_player().set_receiver([this, name](LinkMessage&& message) {
    if (running_) player_->handle_link_message(*name, std::move(message));
  });
  if (vehicle.client) {
    Vehicle* raw = &vehicle;
    vehicle.client->set_on_disconnected([this, raw](const std::string& reason) {
      logger_.info("{}: in-process vehicle client disconnected ({}); reconnecting in {} ms",
                   raw->spec.name, reason, to_whole_ms(config_.reconnect_backoff));
      schedule_reconnect(*raw);
    });
  }
}

// The Streamers first, so that with player_phase 0 the Player's frames fall on their ticks.
void World::start_parts() {
  running_ = true;
  // The Streamers of one executor start on one instant, as they do in virtual time: their frame
  // loops and cameras then share deadlines, one wake-up per frame for them all (each distinct
  // timer instant costs a wake-up, ~20 µs of CPU on a VM: docs/benchmarks.md, issue #41).
  std::vector<std::pair<Executor*, SimTime>> started_at;
  for (auto& vehicle : vehicles_) {
    Executor& on = vehicle->thread ? *vehicle->thread->executor : executor_;
    auto same = std::find_if(started_at.begin(), started_at.end(), [&on](const auto& at) { return at.first == &on; });
    if (same == started_at.end()) same = started_at.insert(started_at.end(), {&on, on.now()});
    vehicle->streamer->start(same->second);
  }
  if (config_.player_phase > Micros{0}) {
    player_start_timer_ = executor_.call_after(config_.player_phase, [this] {
      player_start_timer_ = 0;
      player_->start();
    });
  } else {
    player_->start();
  }
  for (auto& vehicle : vehicles_) {
    if (vehicle->client) connect_in_process_client(*vehicle);
  }
  logger_.info("started: {} vehicle(s), seed {}", vehicles_.size(), config_.seed);
}

void World::stop() {
  if (!running_) return;
  running_ = false;
  for (auto& vehicle : vehicles_) {
    if (vehicle->reconnect_timer != 0) {
      executor_.cancel(vehicle->reconnect_timer);
      vehicle->reconnect_timer = 0;
    }
    if (vehicle->client) vehicle->client->detach();
  }
  if (player_start_timer_ != 0) executor_.cancel(player_start_timer_);
  player_start_timer_ = 0;
  player_->stop();
  for (auto& vehicle : vehicles_) vehicle->streamer->stop();
  logger_.info("stopped");
}

ControlTicker& World::ticker_for(Executor& executor, Micros period) {
  for (auto& shared : tickers_) {
    if (shared->executor == &executor && shared->ticker.period() == period) return shared->ticker;
  }
  // The Streamer threads take turns: thread i of n starts its slots i/n of a slot after thread
  // 0's, so each slot's burst of control frames (and the replies it wakes) has the machine to
  // itself instead of sharing it with every other thread's (docs/benchmarks.md, issue #41).
  const auto thread = std::find_if(streamer_threads_.begin(), streamer_threads_.end(),
                                   [&executor](const StreamerThread& candidate) { return candidate.executor == &executor; });
  const auto turn = static_cast<std::int64_t>(thread == streamer_threads_.end() ? 0 : thread - streamer_threads_.begin());
  const auto turns = static_cast<std::int64_t>(std::max<std::size_t>(streamer_threads_.size(), 1));
  const Micros phase = ControlTicker::slot_step(period, config_.control_tick_slots) * turn / turns;
  tickers_.push_back(std::make_unique<Ticker>(executor, period, config_.control_tick_slots, phase));
  return tickers_.back()->ticker;
}

void World::set_streamer_threads(std::vector<StreamerThread> threads, StreamerThread::Poster post_to_world) {
  streamer_threads_ = std::move(threads);
  post_to_world_ = std::move(post_to_world);
}

bool World::running() const { return running_; }
Executor& World::executor() const { return executor_; }
const WorldConfig& World::config() const { return config_; }

std::vector<std::string> World::vehicles() const {
  std::vector<std::string> names;
  names.reserve(vehicles_.size());
  for (const auto& vehicle : vehicles_) names.push_back(vehicle->spec.name);
  return names;
}

PlayerCore& World::player() { return *player_; }

World::Vehicle& World::find(std::string_view name) const {
  if (const auto found = by_name_.find(name); found != by_name_.end()) return *found->second;
  // Asking for a vehicle the world was not built with is a bug in the caller.
  std::fprintf(stderr, "World: no vehicle named '%.*s' (was start() called?)\n",
               static_cast<int>(name.size()), name.data());
  std::abort();
}

StreamerCore& World::streamer(std::string_view vehicle) { return *find(vehicle).streamer; }
ComChannel& World::link(std::string_view vehicle) { return *find(vehicle).link; }
VehicleClient* World::vehicle_client(std::string_view vehicle) { return find(vehicle).client.get(); }
const StreamTap* World::vehicle_tap(std::string_view vehicle) const { return find(vehicle).tap.get(); }

std::uint64_t World::vehicle_connections(std::string_view vehicle) const {
  return find(vehicle).connections;
}

void World::accept_vehicle_connection(std::string_view vehicle, std::shared_ptr<ByteStream> stream) {
  find(vehicle).streamer->accept_vehicle_connection(std::move(stream));
}

void World::drop_vehicle_connection(std::string_view name) {
  Vehicle& vehicle = find(name);
  if (!vehicle.client || !running_) return;
  logger_.info("{}: dropping the in-process vehicle connection", name);
  // detach() closes the client's end locally: the Streamer sees the peer close; the client
  // gets no callback, so the reconnect is scheduled here.
  vehicle.client->detach();
  schedule_reconnect(vehicle);
}

void World::close_vehicle_connection(std::string_view name, Micros listener_down) {
  Vehicle& vehicle = find(name);
  if (!running_) return;
  if (listener_down > Micros{0}) {
    logger_.info("{}: the Streamer's vehicle port restarts: closed for {} ms", name, to_whole_ms(listener_down));
    vehicle.listening_again_at = executor_.now() + listener_down;
    if (vehicle.listener) vehicle.listener(listener_down);
  }
  vehicle.streamer->close_vehicle_connection();
}

void World::set_vehicle_listener(std::string_view name, VehicleListener listener) {
  find(name).listener = std::move(listener);
}

void World::connect_in_process_client(Vehicle& vehicle) {
  if (executor_.now() < vehicle.listening_again_at) {   // refused: the client backs off and tries again
    schedule_reconnect(vehicle);
    return;
  }
  PipeOptions options;
  options.one_way_delay = config_.vehicle_pipe_delay;
  options.name_a = "pipe:vehicle-client:" + vehicle.spec.name;
  options.name_b = "pipe:streamer:" + vehicle.spec.name;
  PipeEnds ends = make_pipe(executor_, options);
  ++vehicle.connections;
  vehicle.streamer->accept_vehicle_connection(std::move(ends.b));
  std::shared_ptr<ByteStream> client_end = std::move(ends.a);
  if (vehicle.tap) client_end = vehicle.tap->wrap(std::move(client_end));
  vehicle.client->attach(std::move(client_end));
}

void World::schedule_reconnect(Vehicle& vehicle) {
  if (!running_ || vehicle.reconnect_timer != 0) return;
  Vehicle* raw = &vehicle;
  vehicle.reconnect_timer = executor_.call_after(config_.reconnect_backoff, [this, raw] {
    raw->reconnect_timer = 0;
    if (running_) connect_in_process_client(*raw);
  });
}

}  // namespace ocp
