#pragma once
// What the oracle and the generator both need to know about a world from its model alone (no
// core code): when its last disturbance ends, how long recovery may take, and the stall
// windows the fault model must allow for.
#include <optional>
#include <string>
#include <vector>

#include "scenario/model.hpp"

namespace ocp::campaign {

// The bound within which every fault clears and the loop closes after the last disturbance,
// derived from the timers (docs/campaigns.md, "Liveness"): a reconnect (backoff), a read
// timeout that was about to fire, the worst one-way delay a link can still hold back behind
// FIFO order (its largest delay plus one second of bandwidth queue), and two frames of the
// slowest camera; with an operator client, at least the time its connection takes to come back.
Micros liveness_bound(const scenario::Scenario& scenario);

// The time the last timeline action's effect ends (outages, stalls and ramps last; a
// disconnect lasts the reconnect backoff). 0 for an empty timeline.
SimTime quiet_point(const scenario::Scenario& scenario);

struct Window {
  SimTime start{0}, end{0};   // [start, end)
};
// Per vehicle: when its control thread, frame loop, or one of its cameras was stalled.
std::vector<Window> control_thread_stalls(const scenario::Scenario& scenario, const std::string& vehicle);
std::vector<Window> frame_loop_stalls(const scenario::Scenario& scenario, const std::string& vehicle);
std::vector<Window> camera_stalls(const scenario::Scenario& scenario, const std::string& vehicle,
                                  const std::string& camera);

// The largest one-way delay any link is ever set to (start settings and timeline).
Micros largest_delay(const scenario::Scenario& scenario);

}  // namespace ocp::campaign
