#pragma once
// VirtualWorld: a World on its own VirtualExecutor with a TraceRecorder (the JSON Lines event
// trace) and a LogCapture (the log lines, kept apart from the trace) — the harness tests,
// benchmarks and scenarios drive (quinn's Pair / TigerBeetle's simulator, in small).
//
//   VirtualWorld sim(config);              // deterministic_keys forced on
//   ASSERT_TRUE(sim.start());
//   sim.run_for(Millis{500});              // every event with deadline <= now + 500 ms
//   sim.step();                            // exactly one event
//   sim.run_until_condition([&]{ … }, Millis{2000});
#include <cstddef>
#include <functional>

#include "ocp/virtual_executor.hpp"
#include "world/log_capture.hpp"
#include "world/trace.hpp"
#include "world/world.hpp"

namespace ocp {

class VirtualWorld {
 public:
  // `extra_sink` additionally receives every log line (e.g. a console sink while debugging).
  explicit VirtualWorld(WorldConfig config, TraceOptions trace_options = {},
                        LogSink extra_sink = {});

  [[nodiscard]] Status start();   // the trace records the world from its first event

  SimTime now() const { return executor_.now(); }
  bool step() { return executor_.step(); }
  void run_for(Micros duration) { executor_.run_for(duration); }
  void run_until(SimTime end) { executor_.run_until(end); }
  // Runs until `condition` holds (checked after every event) or `limit` of virtual time
  // passed; returns whether it holds. Time stops at the event that made it true.
  bool run_until_condition(const std::function<bool()>& condition, Micros limit);

  VirtualExecutor& executor() { return executor_; }
  World& world() { return world_; }
  TraceRecorder& trace() { return trace_; }
  const LogCapture& log() const { return log_; }

 private:
  VirtualExecutor executor_;
  LogCapture log_;
  World world_;
  TraceRecorder trace_;
};

}  // namespace ocp
