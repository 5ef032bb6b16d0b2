#pragma once
// Timeline actions → calls on the World, scheduled on its executor at their `at` times.
#include <memory>
#include <vector>

#include "scenario/model.hpp"
#include "scenario/runner.hpp"
#include "operator_client.hpp"
#include "world/world.hpp"

namespace ocp::scenario {

// Schedules every event; each one appends itself to `fired` when it runs. `end` bounds
// repeating actions (client data every N ms). The returned handle keeps the actions' state
// (repeating sources) alive: hold it until the run ends. `operator_client`: the stand-in that
// operator_misbehave events act on (nullptr when the world has none; the parser saw to it
// that no such event is then on the timeline).
[[nodiscard]] std::shared_ptr<void> schedule_timeline(World& world, const std::vector<TimelineEvent>& timeline, SimTime end,
                       std::vector<FiredEvent>& fired, SimTime origin = SimTime{0},
                       OperatorClient* operator_client = nullptr);

}  // namespace ocp::scenario
