#pragma once
// Campaign worlds against any vehicle client (ocp_campaign run --client CMD, docs/campaigns.md):
// every vehicle's in-process reference client is replaced by a process of CMD, started by
// /bin/sh -c with "{port}" replaced by its Streamer's port (also in env OCP_PORT), and the
// world runs in real time. The Oracle judges the simulator as in virtual time; ClientWatch
// judges the client's echoes and reconnects from the Streamer's side; and every client process
// must still be running when the world ends.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "campaign/client_watch.hpp"
#include "campaign/world_check.hpp"

namespace ocp::campaign {

struct ClientRun {
  std::string command;              // a shell command line with "{port}"
  std::optional<Micros> max_world;  // cut every world to this long (real time costs wall time)
  ClientBounds bounds;
  std::string log_dir;              // each client's output: <log_dir>/world-<i>-<vehicle>.log; "" → none
};

// The generated world as a client world: external clients, no misbehaviour switches (they
// drive the in-process client only), at most `max_world` long.
scenario::Scenario for_external_client(scenario::Scenario world, std::optional<Micros> max_world);

// Runs one client world (already prepared by for_external_client). `stop` is polled (Ctrl-C).
// A client that cannot be started, or exits before it connects, is outcome.error.
WorldOutcome check_world_with_client(const scenario::Scenario& world, std::uint64_t index, const ClientRun& run,
                                     const std::function<bool()>& stop);

}  // namespace ocp::campaign
