#include "fleet_point.hpp"

#include <fmt/format.h>
#include <malloc.h>
#include <sys/prctl.h>

#include <atomic>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <optional>
#include <thread>

#include "codec_floor.hpp"
#include "kernel_floor.hpp"
#include "ocp/asio/executor.hpp"
#include "ocp/virtual_executor.hpp"
#include "process_usage.hpp"
#include "stats.hpp"
#include "thread_usage.hpp"
#include "sim_app/tcp_front.hpp"
#include "vehicle_app/tcp_runner.hpp"
#include "world/world.hpp"

namespace ocp::bench {

std::string fleet_mode_name(FleetMode mode) { return mode == FleetMode::loopback ? "loopback" : "virtual"; }

std::uint64_t FleetPointResult::faults_total() const {
  std::uint64_t total = 0;
  for (const auto count : faults_raised) total += count;
  return total;
}

namespace {

using Clock = std::chrono::steady_clock;

Micros seconds_to_micros(double seconds) { return Micros{static_cast<std::int64_t>(seconds * 1e6)}; }

std::vector<std::string> vehicle_names(const WorldConfig& config) {
  std::vector<std::string> names;
  for (const auto& vehicle : config.vehicles) names.push_back(vehicle.name);
  return names;
}

WorldConfig fleet_config(int vehicles, bool in_process_clients, std::size_t tick_slots) {
  WorldConfig config;
  config.seed = 11;
  config.deterministic_keys = in_process_clients;   // virtual time: reproducible
  config.player.name = "operator";
  config.player.fleet = true;
  config.control_tick_slots = tick_slots;
  for (int index = 0; index < vehicles; ++index) {
    VehicleSpec vehicle;
    vehicle.name = fmt::format("v{:05}", index);
    vehicle.in_process_client = in_process_clients;
    config.vehicles.push_back(std::move(vehicle));
  }
  return config;
}

void fail(FleetPointResult& result, const std::string& why) {
  result.ok = false;
  std::strncpy(result.error, why.c_str(), sizeof result.error - 1);
}

void take_figures(FleetPointResult& result, const FleetRecorder& recorder) {
  const Summary ticks = summarize(recorder.tick_lateness_us());
  const Summary echoes = summarize(recorder.echo_delays_us());
  result.ticks = ticks.count;
  result.tick_p50_us = ticks.p50;
  result.tick_p99_us = ticks.p99;
  result.tick_max_us = ticks.max;
  result.echoes = echoes.count;
  result.echo_p50_us = echoes.p50;
  result.echo_p99_us = echoes.p99;
  result.responses = recorder.responses();
  result.connections = recorder.connections();
  result.control_bytes = recorder.mean_control_bytes();
  result.response_bytes = recorder.mean_response_bytes();
  for (std::size_t id = 0; id < fault_count; ++id) result.faults_raised[id] = recorder.faults_raised()[id];
}

// The point's measured window: wall time, the process's CPU and each thread's share.
class MeasuredWindow {
 public:
  MeasuredWindow() : threads_(sample_threads()), cpu_start_(process_cpu_seconds()), wall_start_(Clock::now()) {}
  // Writes wall_s, cpu_s, rss_end_kib and the threads into `result`.
  void finish(FleetPointResult& result) const {
    result.wall_s = std::chrono::duration<double>(Clock::now() - wall_start_).count();
    result.cpu_s = process_cpu_seconds() - cpu_start_;
    result.rss_end_kib = resident_kib();
    const std::vector<ThreadSample> used = thread_usage_between(threads_, sample_threads());
    result.thread_count = static_cast<int>(std::min(used.size(), std::size(result.threads)));
    std::copy_n(used.begin(), result.thread_count, result.threads);
  }

 private:
  std::vector<ThreadSample> threads_;
  double cpu_start_;
  Clock::time_point wall_start_;
};

// Reference clients (VehicleClient + TcpRunner), each connecting to one port, on one executor
// or several: ClientFleet's threads hold one set each; with --client-threads 0 one set holds
// every client, each on its own Streamer's executor, added before those executors run (the
// traffic's two ends then share a thread, as in the kernel floor, and a frame wakes no other
// thread).
class ClientSet {
 public:
  void add(AsioExecutor& executor, std::uint16_t port) {
    // The model ticks of an executor's clients on one grid (model_step): one wake-up per model
    // period for them all, not one per client at its own phase (~20 µs of CPU each on a VM).
    VehicleClientConfig client;
    client.model_grid = client.model_step;
    // A control message comes every 10 ms, so a keep-alive check never sends here; with a
    // period of slack it rides the thread's next model tick or ticker slot. With the default
    // 1 ms, each slot's clients woke their thread once more per period, ~1 ms after the slot:
    // 5 extra sleeps per period per thread at 5 slots (docs/benchmarks.md, issue #41).
    client.keepalive_slack = client.response_period;
    clients_.push_back(std::make_unique<VehicleClient>(executor, client, Logger(executor, "vehicle", {})));
    TcpRunnerConfig config;
    config.server.port = port;
    runners_.push_back(std::make_unique<TcpRunner>(executor, *clients_.back(), config, Logger(executor, "tcp", {})));
    runners_.back()->start();
  }
  // On the executors' threads, or once they have stopped.
  void stop() {
    for (auto& runner : runners_) runner->stop();
  }
  void clear() {
    runners_.clear();   // before the clients they drive
    clients_.clear();
  }

 private:
  std::vector<std::unique_ptr<VehicleClient>> clients_;
  std::vector<std::unique_ptr<TcpRunner>> runners_;
};

// N reference clients spread over `threads` threads (vehicle i's client on thread i % threads),
// each thread with its own io_context, as that many client processes would be. One thread for
// a whole fleet was the saturated one (issue #41: at 1 000 vehicles it needs several cores).
class ClientFleet {
 public:
  ClientFleet(const std::vector<std::uint16_t>& ports, int threads) {
    if (threads <= 0) return;   // the clients are on the Streamers' executors (ClientSet)
    const std::size_t count = static_cast<std::size_t>(threads);
    for (std::size_t index = 0; index < count; ++index) workers_.push_back(std::make_unique<Worker>());
    std::vector<std::vector<std::uint16_t>> ports_of(count);
    for (std::size_t vehicle = 0; vehicle < ports.size(); ++vehicle) ports_of[vehicle % count].push_back(ports[vehicle]);
    for (std::size_t index = 0; index < count; ++index) {
      workers_[index]->thread = std::thread([worker = workers_[index].get(), index, mine = std::move(ports_of[index])] {
        worker->run(index, mine);
      });
    }
  }
  ~ClientFleet() { stop(); }
  // The runners stop on their own threads, then each io_context.
  void stop() {
    for (auto& worker : workers_) {
      boost::asio::post(worker->io, [worker = worker.get()] {
        worker->clients.stop();
        worker->work.reset();
        worker->io.stop();
      });
    }
    for (auto& worker : workers_) {
      if (worker->thread.joinable()) worker->thread.join();
    }
  }

 private:
  struct Worker {
    // Concurrency hint 1: one thread runs it (the stop() post is the only cross-thread call).
    boost::asio::io_context io{1};
    boost::asio::executor_work_guard<boost::asio::io_context::executor_type> work = boost::asio::make_work_guard(io);
    ClientSet clients;
    std::thread thread;

    void run(std::size_t index, const std::vector<std::uint16_t>& ports) {
      prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
      name_this_thread(fmt::format("clients-{}", index).c_str());
      AsioExecutor executor(io);
      for (const std::uint16_t port : ports) clients.add(executor, port);
      io.run();
      clients.clear();   // before the executor they use goes
    }
  };
  std::vector<std::unique_ptr<Worker>> workers_;
};

// The threads the Streamers live on (World::set_streamer_threads): each its own io_context
// and executor, so a Streamer's ticks, its socket and its recorder share one thread.
class StreamerThreads {
 public:
  explicit StreamerThreads(int count) {
    for (int index = 0; index < count; ++index) workers_.push_back(std::make_unique<Worker>());
  }
  ~StreamerThreads() { stop(); }

  std::size_t size() const { return workers_.size(); }
  std::vector<StreamerThread> threads() {
    std::vector<StreamerThread> threads;
    for (auto& worker : workers_) {
      threads.push_back({&worker->executor, [io = &worker->io](std::function<void()> task) {
                           boost::asio::post(*io, std::move(task));
                         }});
    }
    return threads;
  }
  // Vehicle i lives on thread i % size(), as World places it.
  AsioExecutor& executor_of(std::size_t vehicle) { return workers_[vehicle % workers_.size()]->executor; }

  void start() {
    for (auto& worker : workers_) {
      const std::string name = fmt::format("streamers-{}", &worker - workers_.data());
      worker->thread = std::thread([io = &worker->io, name] {
        prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
        name_this_thread(name.c_str());   // the per-thread report, perf --sort comm
        auto work = boost::asio::make_work_guard(*io);
        io->run();
      });
    }
  }
  void stop() {
    for (auto& worker : workers_) {
      worker->io.stop();
      if (worker->thread.joinable()) worker->thread.join();
    }
  }

 private:
  struct Worker {
    boost::asio::io_context io;
    AsioExecutor executor{io};
    std::thread thread;
  };
  std::vector<std::unique_ptr<Worker>> workers_;
};

// One recorder per Streamer thread, each on the buses of that thread's Streamers.
std::vector<std::unique_ptr<FleetRecorder>> recorders_per_thread(World& world, const std::vector<std::string>& names,
                                                                 std::size_t threads) {
  std::vector<std::vector<EventBus*>> buses(threads);
  for (std::size_t vehicle = 0; vehicle < names.size(); ++vehicle) {
    buses[vehicle % threads].push_back(&world.streamer(names[vehicle]).events());
  }
  std::vector<std::unique_ptr<FleetRecorder>> recorders;
  for (const auto& some : buses) recorders.push_back(std::make_unique<FleetRecorder>(some));
  return recorders;
}

// Runs the main io_context until every client has connected or options.connect_timeout_s has
// passed; the connections counted.
std::uint64_t wait_for_connections(boost::asio::io_context& io, const std::vector<std::unique_ptr<FleetRecorder>>& recorders,
                                   const FleetPointOptions& options) {
  auto connections = [&recorders] {
    std::uint64_t total = 0;
    for (const auto& recorder : recorders) total += recorder->connections();
    return total;
  };
  const auto give_up = Clock::now() + std::chrono::duration<double>(options.connect_timeout_s);
  while (connections() < static_cast<std::uint64_t>(options.vehicles) && Clock::now() < give_up) {
    io.run_for(std::chrono::milliseconds(100));
  }
  return connections();
}

FleetPointResult run_loopback(const FleetPointOptions& options, FleetPointResult result) {
  prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
  // One malloc arena for every thread of the point. Link messages are built on one thread and
  // freed on another; with glibc's arena per thread those frees contend for the builder's
  // arena lock, and the threads sleep on it (1 000 vehicles, load ≈ 6.6, 2026-11-22: 0.67 CPU
  // s/s and 5.5 % of the ticks run with an arena per thread, 1.2–1.3 CPU s/s and 16 % with one).
  mallopt(M_ARENA_MAX, 1);
  // Per vehicle: the Streamer's listening and accepted sockets and the client's.
  make_room_for_descriptors(3 * static_cast<std::size_t>(options.vehicles));
  result.rss_base_kib = resident_kib();
  boost::asio::io_context io;
  AsioExecutor executor(io);
  StreamerThreads streamer_threads(options.streamer_threads);   // before the World: outlives its sockets
  const WorldConfig config = fleet_config(options.vehicles, false, options.control_tick_slots);
  const std::vector<std::string> names = vehicle_names(config);   // world.vehicles() is empty until start()
  World world(executor, config, make_null_sink());
  const bool threaded = streamer_threads.size() > 0;
  if (threaded) {
    world.set_streamer_threads(streamer_threads.threads(),
                               [&io](std::function<void()> task) { boost::asio::post(io, std::move(task)); });
  }
  std::vector<std::unique_ptr<sim_app::TcpFront>> fronts;
  ClientSet hosted;   // --client-threads 0; after the executors and fronts: goes first
  std::vector<std::uint16_t> ports;
  auto executor_of = [&](std::size_t vehicle) -> AsioExecutor& {
    return threaded ? streamer_threads.executor_of(vehicle) : executor;
  };
  for (std::size_t vehicle = 0; vehicle < names.size(); ++vehicle) {
    AsioExecutor& front_executor = executor_of(vehicle);
    fronts.push_back(sim_app::vehicle_api_front(front_executor, world, names[vehicle], Logger(front_executor, "front", {})));
    if (auto status = fronts.back()->listen(TcpServerOptions{0, false}); !status) {
      fail(result, "listen: " + status.error().detail);
      return result;
    }
    ports.push_back(fronts.back()->port());
  }
  std::vector<std::unique_ptr<FleetRecorder>> recorders;
  if (!threaded) recorders.push_back(std::make_unique<FleetRecorder>(world.events(), names));
  if (auto status = world.start(); !status) {
    fail(result, "world: " + status.error().detail);
    return result;
  }
  if (threaded) recorders = recorders_per_thread(world, names, streamer_threads.size());
  if (options.client_threads == 0) {
    for (std::size_t vehicle = 0; vehicle < names.size(); ++vehicle) hosted.add(executor_of(vehicle), ports[vehicle]);
  }
  streamer_threads.start();
  ClientFleet clients(ports, options.client_threads);
  auto shut_down = [&] {
    clients.stop();
    streamer_threads.stop();   // before the World stops: its Streamers are theirs until then
    hosted.stop();
    for (auto& front : fronts) front->stop();
    world.stop();
  };
  if (const std::uint64_t connected = wait_for_connections(io, recorders, options);
      connected < static_cast<std::uint64_t>(options.vehicles)) {
    shut_down();
    fail(result, fmt::format("only {} of {} clients connected", connected, options.vehicles));
    return result;
  }
  io.run_for(seconds_to_micros(options.warm_up_s));
  const MeasuredWindow window;
  for (auto& recorder : recorders) recorder->start_recording();
  io.run_for(seconds_to_micros(options.window_s));
  for (auto& recorder : recorders) recorder->stop_recording();
  window.finish(result);
  result.window_s = result.wall_s;
  shut_down();
  for (std::size_t index = 1; index < recorders.size(); ++index) recorders.front()->merge(*recorders[index]);
  take_figures(result, *recorders.front());
  result.ok = true;
  return result;
}

// After the window (so not in the point's cpu_s), with the World stopped.
void add_codec_floor(const FleetPointOptions& options, const FleetRecorder& recorder, FleetPointResult& result) {
  if (recorder.sample_control().empty() || recorder.sample_response().empty()) {
    std::snprintf(result.codec_floor_error, sizeof result.codec_floor_error, "no frames recorded to take as samples");
    return;
  }
  const CodecFloor floor =
      measure_codec_floor(options.vehicles, recorder.sample_control(), recorder.sample_response(), options.codec_floor_s);
  if (!floor.ok) {
    std::snprintf(result.codec_floor_error, sizeof result.codec_floor_error, "%s", floor.error.c_str());
    return;
  }
  result.codec_floor_measured = true;
  result.codec_floor_us_per_vehicle_cycle = floor.us_per_vehicle_cycle;
  result.codec_floor_cpu_per_s = floor.cpu_per_simulated_s;
}

FleetPointResult run_virtual(const FleetPointOptions& options, FleetPointResult result) {
  result.rss_base_kib = resident_kib();
  VirtualExecutor executor;
  const WorldConfig config = fleet_config(options.vehicles, true, options.control_tick_slots);
  World world(executor, config, make_null_sink());
  std::optional<FleetRecorder> recorder;
  if (options.observe) recorder.emplace(world.events(), vehicle_names(config));
  if (auto status = world.start(); !status) {
    fail(result, "world: " + status.error().detail);
    return result;
  }
  executor.run_for(seconds_to_micros(options.warm_up_s));
  const MeasuredWindow window;
  if (recorder) recorder->start_recording();
  executor.run_for(seconds_to_micros(options.window_s));
  if (recorder) recorder->stop_recording();
  window.finish(result);
  result.window_s = options.window_s;
  world.stop();
  if (recorder) {
    take_figures(result, *recorder);
    if (options.codec_floor_s > 0) add_codec_floor(options, *recorder, result);
  }
  result.ok = true;
  return result;
}

// The paced floor's cost is paid per burst, and 0.4 s is only 40 periods of them, which vary
// from run to run; a second (100 periods) settles it.
constexpr double paced_floor_min_s = 1.0;

// After the window and with the point's sockets closed, so they are neither in the point's cpu_s
// nor competing with it.
void add_kernel_floors(const FleetPointOptions& options, FleetPointResult& result) {
  if (result.control_bytes < 1 || result.response_bytes < 1) {
    for (char* error : {result.kernel_floor_error, result.paced_floor_error}) {
      std::snprintf(error, sizeof result.kernel_floor_error, "no frames recorded to size it on");
    }
    return;
  }
  const auto control_bytes = static_cast<std::size_t>(std::lround(result.control_bytes));
  const auto response_bytes = static_cast<std::size_t>(std::lround(result.response_bytes));
  const KernelFloor floor =
      measure_kernel_floor(options.vehicles, control_bytes, response_bytes, options.kernel_floor_s);
  if (floor.ok) {
    result.kernel_floor_measured = true;
    result.kernel_floor_us_per_vehicle_tick = floor.us_per_vehicle_tick;
    result.kernel_floor_cpu_per_s = floor.cpu_per_s_at_100hz;
  } else {
    std::snprintf(result.kernel_floor_error, sizeof result.kernel_floor_error, "%s", floor.error.c_str());
  }
  const PacedShape shape = paced_floor_shape(options.vehicles, options.streamer_threads, options.client_threads,
                                             static_cast<int>(options.control_tick_slots));
  const KernelFloor paced = measure_paced_kernel_floor(shape, control_bytes, response_bytes,
                                                       std::max(paced_floor_min_s, options.kernel_floor_s));
  if (paced.ok) {
    result.paced_floor_measured = true;
    result.paced_floor_us_per_vehicle_tick = paced.us_per_vehicle_tick;
    result.paced_floor_cpu_per_s = paced.cpu_per_s_at_100hz;
    result.paced_floor_wall_s = paced.wall_s;
  } else {
    std::snprintf(result.paced_floor_error, sizeof result.paced_floor_error, "%s", paced.error.c_str());
  }
}

}  // namespace

PacedShape paced_floor_shape(int vehicles, int streamer_threads, int client_threads, int tick_slots) {
  return {vehicles, std::clamp(streamer_threads, 1, std::max(1, vehicles)), client_threads > 0, std::max(1, tick_slots)};
}

FleetPointResult run_fleet_point(const FleetPointOptions& options) {
  FleetPointResult result;
  result.mode = options.mode;
  result.vehicles = options.vehicles;
  result.observed = options.observe;
  result.control_tick_slots = static_cast<int>(options.control_tick_slots);
  result.streamer_threads = options.mode == FleetMode::loopback ? options.streamer_threads : 0;
  result.client_threads = options.mode == FleetMode::loopback ? options.client_threads : 0;
  // The main thread runs the World: the Player (and, with no Streamer threads, the Streamers;
  // in virtual time the whole fleet).
  const ScopedThreadName main_thread(options.mode == FleetMode::loopback ? "player" : "world");
  result = options.mode == FleetMode::loopback ? run_loopback(options, result) : run_virtual(options, result);
  if (result.ok && options.mode == FleetMode::loopback && options.kernel_floor_s > 0) {
    add_kernel_floors(options, result);
  }
  if (result.ok) {
    result.cpu_per_simulated_s = result.window_s > 0 ? result.cpu_s / result.window_s : 0;
    result.simulated_per_wall_s = result.wall_s > 0 ? result.window_s / result.wall_s : 0;
    result.kib_per_vehicle = (result.rss_end_kib - result.rss_base_kib) / std::max(1, result.vehicles);
  }
  return result;
}

}  // namespace ocp::bench
