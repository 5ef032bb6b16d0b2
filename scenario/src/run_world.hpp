#pragma once
// The clock-independent part of a run, shared by virtual-time and real-time runs: builds the
// World on `executor`, attaches trace and Observer, schedules the timeline relative to the
// executor's time at start, then lets `drive` run the clock to the end.
#include <functional>

#include "ocp/executor.hpp"
#include "scenario/runner.hpp"
#include "world/world.hpp"

namespace ocp::scenario {

// Runs the executor until `end` (absolute), or until the run is interrupted; returns the time
// it stopped at. Called once, with the started World.
using ClockDriver = std::function<SimTime(World& world, SimTime end)>;

RunResult run_world(Executor& executor, const Scenario& scenario, const RunOptions& options,
                    bool deterministic_keys, const ClockDriver& drive);

}  // namespace ocp::scenario
