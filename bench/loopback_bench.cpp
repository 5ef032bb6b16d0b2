// Loopback benchmarks of the vehicle-side TCP front (issue #5), real time, real sockets:
//   * echo round trip: a control frame leaving the Streamer → the response carrying its pair
//     arriving back (immediate-echo client = the reference VehicleClient on its own thread);
//   * tick lateness of a 100 Hz PeriodicTimer on the AsioExecutor, idle and beside a running
//     Streamer with a connected vehicle;
//   * CPU per connected vehicle at 100 Hz (getrusage(RUSAGE_THREAD) of the Streamer thread with
//     and without a vehicle, and of the client's thread);
//   * the machine's floors, measured in the same run: a bare sleep_until loop for tick
//     lateness, a bare blocking-socket echo paced the same way for the echo.
// Each benchmark runs once for a fixed wall-clock window and reports percentiles as counters.
// Results: docs/benchmarks.md ("Loopback").
#include <benchmark/benchmark.h>
#include <sys/prctl.h>
#include <sys/resource.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/read.hpp>
#include <boost/asio/write.hpp>
#include <chrono>
#include <cstdint>
#include <thread>
#include <unordered_map>
#include <vector>

#include "loop/floor_echo.hpp"
#include "ocp/asio/executor.hpp"
#include "streamer_app/streamer_simulation.hpp"
#include "vehicle_app/tcp_runner.hpp"

namespace ocp {
namespace {

constexpr std::chrono::seconds measure_window{5};
constexpr std::chrono::seconds warm_up{1};

// As sim_app::RealTimeRunner does for the executables: no 50 µs default timer slack.
void use_precise_timers() { prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL); }

double thread_cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_THREAD, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) / 1e6;
}

double percentile(std::vector<double> values, double fraction) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const auto index = static_cast<std::size_t>(fraction * static_cast<double>(values.size() - 1));
  return values[index];
}

// The reference vehicle client on its own thread and io_context, as a separate process would be.
class ClientThread {
 public:
  explicit ClientThread(std::uint16_t port) {
    thread_ = std::thread([this, port] {
      use_precise_timers();
      boost::asio::io_context io;
      AsioExecutor executor(io);
      VehicleClient client(executor, VehicleClientConfig{}, Logger(executor, "vehicle", {}));
      TcpRunnerConfig config;
      config.server.port = port;
      TcpRunner runner(executor, client, config, Logger(executor, "vehicle:tcp", {}));
      runner.start();
      const double cpu_start = thread_cpu_seconds();
      const auto wall_start = std::chrono::steady_clock::now();
      while (!stop_) io.run_for(std::chrono::milliseconds(50));
      cpu_seconds_ = thread_cpu_seconds() - cpu_start;
      wall_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
      runner.stop();
    });
  }
  ~ClientThread() { join(); }
  void join() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
  }
  double cpu_percent() const { return wall_seconds_ > 0 ? 100.0 * cpu_seconds_ / wall_seconds_ : 0.0; }

 private:
  std::thread thread_;
  std::atomic<bool> stop_{false};
  double cpu_seconds_ = 0.0;
  double wall_seconds_ = 0.0;
};

// Control frame sent (by ack_time) → the first response that carries that pair, from the
// Streamer's event stream (WireFrame events carry the pair of each frame).
class RoundTripProbe {
 public:
  explicit RoundTripProbe(EventBus& events)
      : subscription_(events.subscribe([this](const Event& event) {
          const auto* frame = std::get_if<WireFrame>(&event.body);
          if (frame != nullptr && frame->ack) on_frame(*frame, event.time);
        })) {}
  void on_frame(const WireFrame& frame, SimTime at) {
    if (frame.direction == FrameDirection::out) {
      sent_at_[frame.ack->ack_time] = at;
      return;
    }
    const auto found = sent_at_.find(frame.ack->ack_time);
    if (found == sent_at_.end()) return;   // keep-alive repeat of a pair already counted
    if (recording_) round_trips_us_.push_back(static_cast<double>((at - found->second).count()));
    sent_at_.erase(found);
  }
  void start_recording() {
    recording_ = true;
    round_trips_us_.clear();
  }
  const std::vector<double>& round_trips_us() const { return round_trips_us_; }

 private:
  std::unordered_map<std::uint64_t, SimTime> sent_at_;
  std::vector<double> round_trips_us_;
  bool recording_ = false;
  EventBus::Subscription subscription_;
};

// Lateness of every tick of a 100 Hz PeriodicTimer.
class TickProbe {
 public:
  explicit TickProbe(Executor& executor)
      : executor_(executor), timer_(executor, Micros{10'000}, [this](SimTime deadline) {
          lateness_us_.push_back(static_cast<double>((executor_.now() - deadline).count()));
        }) {}
  void start() {
    lateness_us_.clear();
    timer_.start(executor_.now() + Micros{10'000});
  }
  void stop() { timer_.stop(); }
  const std::vector<double>& lateness_us() const { return lateness_us_; }

 private:
  Executor& executor_;
  PeriodicTimer timer_;
  std::vector<double> lateness_us_;
};

void report_percentiles(benchmark::State& state, const std::string& prefix, const std::vector<double>& values) {
  state.counters[prefix + "p50_us"] = percentile(values, 0.50);
  state.counters[prefix + "p90_us"] = percentile(values, 0.90);
  state.counters[prefix + "p99_us"] = percentile(values, 0.99);
  state.counters[prefix + "max_us"] = values.empty() ? 0.0 : *std::max_element(values.begin(), values.end());
  state.counters[prefix + "samples"] = static_cast<double>(values.size());
}

// What `streamer_sim` runs, on an ephemeral port, driven by this thread's io_context.
struct StreamerUnderTest {
  boost::asio::io_context io;
  AsioExecutor executor{io};
  StreamerSimulation simulation{executor, ephemeral_port_options(), {}};

  static StreamerSimOptions ephemeral_port_options() {
    StreamerSimOptions options;
    options.plugin_params.tcp_port = 0;
    // As in `ocp_bench loop`: the simulated operator's frame not inside the echo's round trip.
    options.operator_phase = Micros{1'250};
    return options;
  }
};

double cpu_percent_of_window(double cpu_seconds) {
  return 100.0 * cpu_seconds / static_cast<double>(measure_window.count());
}

void BM_LoopbackEchoRoundTrip(benchmark::State& state) {
  use_precise_timers();
  for (auto _ : state) {
    StreamerUnderTest streamer;
    auto& [io, executor, simulation] = streamer;
    if (!simulation.start().ok()) {
      state.SkipWithError("cannot start the streamer");
      return;
    }
    RoundTripProbe probe(simulation.streamer().events());
    TickProbe ticks(executor);
    ClientThread client(simulation.port());
    io.run_for(warm_up);
    probe.start_recording();
    ticks.start();
    const double cpu_start = thread_cpu_seconds();
    io.run_for(measure_window);
    const double streamer_cpu = thread_cpu_seconds() - cpu_start;
    ticks.stop();
    client.join();
    report_percentiles(state, "echo_", probe.round_trips_us());
    report_percentiles(state, "tick_late_", ticks.lateness_us());
    state.counters["streamer_thread_cpu_pct"] = cpu_percent_of_window(streamer_cpu);
    state.counters["client_thread_cpu_pct"] = client.cpu_percent();
    state.counters["control_frames"] = static_cast<double>(simulation.streamer().stats().control_frames_sent);
  }
}
BENCHMARK(BM_LoopbackEchoRoundTrip)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

// The same Streamer world without a vehicle: the baseline the per-vehicle CPU is measured from.
void BM_StreamerWithoutVehicle(benchmark::State& state) {
  use_precise_timers();
  for (auto _ : state) {
    StreamerUnderTest streamer;
    if (!streamer.simulation.start().ok()) {
      state.SkipWithError("cannot start the streamer");
      return;
    }
    streamer.io.run_for(warm_up);
    const double cpu_start = thread_cpu_seconds();
    streamer.io.run_for(measure_window);
    state.counters["streamer_thread_cpu_pct"] = cpu_percent_of_window(thread_cpu_seconds() - cpu_start);
  }
}
BENCHMARK(BM_StreamerWithoutVehicle)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

void BM_TickLatenessIdle100Hz(benchmark::State& state) {
  use_precise_timers();
  for (auto _ : state) {
    boost::asio::io_context io;
    AsioExecutor executor(io);
    TickProbe ticks(executor);
    ticks.start();
    io.run_for(measure_window);
    ticks.stop();
    report_percentiles(state, "tick_late_", ticks.lateness_us());
  }
}
BENCHMARK(BM_TickLatenessIdle100Hz)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

using SteadyTime = std::chrono::steady_clock::time_point;

double micros_since(SteadyTime start) {
  return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
}

// The floors' pacing: wakes every 10 ms on absolute deadlines for the measurement window and
// collects what `measure(deadline)` returns.
template <typename Measure>
std::vector<double> every_10ms(Measure measure) {
  std::vector<double> values;
  const auto samples = static_cast<std::size_t>(measure_window / std::chrono::milliseconds(10));
  SteadyTime deadline = std::chrono::steady_clock::now();
  for (std::size_t index = 0; index < samples; ++index) {
    deadline += std::chrono::milliseconds(10);
    std::this_thread::sleep_until(deadline);
    values.push_back(measure(deadline));
  }
  return values;
}

// The machine's floor for the tick-lateness figures, in the same run: a bare sleep_until loop
// at 100 Hz on absolute deadlines (no executor, no reactor).
void BM_BareSleepUntilFloor100Hz(benchmark::State& state) {
  use_precise_timers();
  for (auto _ : state) {
    report_percentiles(state, "tick_late_", every_10ms([](SteadyTime deadline) { return micros_since(deadline); }));
  }
}
BENCHMARK(BM_BareSleepUntilFloor100Hz)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

// The machine's floor for the echo figure, in the same run: two threads, plain blocking
// sockets, a frame of the control message's size sent every 10 ms on absolute deadlines and
// echoed at once. No Streamer, no client, no reactor: only the kernel's loopback and two
// thread wake-ups, which on a VM can dominate (see docs/benchmarks.md).
void BM_BareSocketEchoFloor(benchmark::State& state) {
  for (auto _ : state) {
    bench::FloorEcho floor;   // the same floor `ocp_bench loop --compare` measures
    std::this_thread::sleep_for(measure_window);
    floor.stop();
    report_percentiles(state, "echo_", floor.round_trips_us());
  }
}
BENCHMARK(BM_BareSocketEchoFloor)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

}  // namespace
}  // namespace ocp
