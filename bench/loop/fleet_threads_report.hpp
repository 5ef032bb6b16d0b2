#pragma once
// The per-thread part of `ocp_bench fleet`'s report: each thread of a point's process over its
// window, as a table (text) and an array (JSON), with the busiest thread named, so the one that
// limits the point shows (issue #41).
#include <ostream>
#include <string>

#include "fleet_point.hpp"

namespace ocp::bench {

// A thread runnable (on a core or waiting for one) for at least this share of the window is
// called saturated: it had work all the time, whether or not the machine gave it a core.
inline constexpr double saturated_share = 0.9;

void print_thread_table(std::ostream& out, const FleetPointResult& point);
std::string threads_json(const FleetPointResult& point);

}  // namespace ocp::bench
