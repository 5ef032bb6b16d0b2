// Virtual-time world speed (issue #3 "Performance"): one simulated hour of a one-vehicle world
// — 100 Hz control, two 30 fps cameras, 40 ms link delay with jitter each way, the reference
// vehicle client in-process over a pipe — must take at most 2 s of wall time with flat memory.
//
//   build-*/bench/world_bench --benchmark_filter=OneHour
//   build-*/bench/world_bench --benchmark_filter=TraceLink   # same world, trace-driven link
//
// Counters: events run by the executor (and per CPU second), resident memory after 1 minute
// and after the full run (flat memory ⇒ equal within noise), control frames and responses.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

#include "loop/process_usage.hpp"
#include "ocp/com_channel.hpp"
#include "ocp/delivery_trace.hpp"
#include "ocp/virtual_executor.hpp"
#include "world/world.hpp"

namespace {

using namespace ocp;

using ocp::bench::resident_kib;

// 24 Mbit/s (two 1500-byte opportunities per millisecond), looping every second: the
// trace-driven link's cost per message, against the fixed-delay link of the same world.
std::shared_ptr<const DeliveryTrace> constant_trace() {
  std::string text;
  for (int ms = 1; ms <= 1000; ++ms) text += std::to_string(ms) + "\n" + std::to_string(ms) + "\n";
  return std::make_shared<const DeliveryTrace>(DeliveryTrace::parse(text, "24mbps").value());
}

WorldConfig bench_config(bool trace_link) {
  WorldConfig config;
  config.seed = 7;
  config.deterministic_keys = true;
  VehicleSpec vehicle;
  vehicle.name = "truck-1";
  vehicle.streamer.cameras = {CameraConfig{"front", 30.0}, CameraConfig{"rear", 30.0}};
  Impairments link;
  link.delay = Millis{40};
  link.jitter_kind = Impairments::JitterKind::uniform;
  link.jitter = Millis{5};
  if (trace_link) link.trace = constant_trace();
  vehicle.to_streamer = link;
  vehicle.to_player = link;
  config.vehicles.push_back(vehicle);
  return config;
}

void run_world(benchmark::State& state, Micros simulated, bool trace_link = false) {
  for (auto _ : state) {
    state.PauseTiming();
    const double rss_before = resident_kib();
    VirtualExecutor executor;
    World world(executor, bench_config(trace_link), make_null_sink());
    if (!world.start()) {
      state.SkipWithError("world did not start");
      return;
    }
    // The operator drives: a slow steering wave with some throttle.
    Waveform waveform;
    waveform.base.axes.right_trigger = 0.2;
    waveform.waves.push_back(SineWave{GamepadAxis::left_x, 0.5, Micros{8'000'000}, 0.0});
    world.player().gamepad().set_waveform(waveform);
    state.ResumeTiming();

    const Micros first_part = std::min<Micros>(simulated, Micros{60'000'000});
    executor.run_for(first_part);
    state.PauseTiming();
    const double rss_after_first_minute = resident_kib();
    state.ResumeTiming();
    executor.run_for(simulated - first_part);

    state.PauseTiming();
    const double rss_after = resident_kib();
    StreamerCore& streamer = world.streamer("truck-1");
    state.counters["events"] = static_cast<double>(executor.events_run());
    state.counters["events_per_second"] =
        benchmark::Counter(static_cast<double>(executor.events_run()), benchmark::Counter::kIsRate);
    state.counters["control_frames"] = static_cast<double>(streamer.stats().control_frames_sent);
    state.counters["vehicle_responses"] = static_cast<double>(streamer.stats().vehicle_responses_received);
    state.counters["video_frames"] = static_cast<double>(streamer.stats().video_frames_sent);
    state.counters["rss_start_kib"] = rss_before;
    state.counters["rss_1min_kib"] = rss_after_first_minute;
    state.counters["rss_end_kib"] = rss_after;
    state.counters["faults_at_end"] = static_cast<double>(streamer.faults().to_vector().size());
    world.stop();
    state.ResumeTiming();
  }
}

void BM_WorldOneHour(benchmark::State& state) { run_world(state, Micros{3'600'000'000}); }
BENCHMARK(BM_WorldOneHour)->Unit(benchmark::kMillisecond)->Iterations(1);

// Short run for profiling (valgrind --tool=callgrind … --benchmark_filter=OneMinute).
void BM_WorldOneMinute(benchmark::State& state) { run_world(state, Micros{60'000'000}); }
BENCHMARK(BM_WorldOneMinute)->Unit(benchmark::kMillisecond);

// The link alone, per message: 3 kB video frames (2 packets) every millisecond (24 Mbit/s
// offered) through one direction, 40 ms ± 5 ms, without and with the 24 Mbit/s trace (which
// carries them all, queueing some): the trace-driven link's cost per message against the
// fixed-delay link's.
void run_link(benchmark::State& state, bool trace_link) {
  constexpr int messages = 200'000;
  Impairments impairments;
  impairments.delay = Millis{40};
  impairments.jitter_kind = Impairments::JitterKind::uniform;
  impairments.jitter = Millis{5};
  if (trace_link) impairments.trace = constant_trace();
  for (auto _ : state) {
    VirtualExecutor executor;
    LinkDirection link(executor, 7);
    link.set_impairments(impairments);
    std::uint64_t delivered = 0;
    link.set_receiver([&delivered](LinkMessage&&) { ++delivered; });
    VideoFrame frame{"front", 0, std::nullopt, 2900};
    for (int i = 0; i < messages; ++i) {
      executor.run_until(SimTime{i * 1000});
      frame.frame_number = static_cast<std::uint64_t>(i);
      link.send(frame);
    }
    executor.run_for(Micros{10'000'000});
    benchmark::DoNotOptimize(delivered);
    state.counters["delivered"] = static_cast<double>(delivered);
  }
  state.SetItemsProcessed(state.iterations() * messages);
}
void BM_LinkFixedDelay(benchmark::State& state) { run_link(state, false); }
BENCHMARK(BM_LinkFixedDelay)->Unit(benchmark::kMillisecond);
void BM_LinkTrace(benchmark::State& state) { run_link(state, true); }
BENCHMARK(BM_LinkTrace)->Unit(benchmark::kMillisecond);

void BM_WorldOneHourTraceLink(benchmark::State& state) { run_world(state, Micros{3'600'000'000}, true); }
BENCHMARK(BM_WorldOneHourTraceLink)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
