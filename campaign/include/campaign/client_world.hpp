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
#include <vector>

#include "campaign/client_watch.hpp"
#include "campaign/world_check.hpp"
#include "vtime/controller.hpp"

namespace ocp::campaign {

enum class ClientTime { virtual_time, real_time };

struct ClientRun {
  std::string command;              // a shell command line with "{port}"
  // Virtual: the client processes live on the World's clock (vtime/, docs/virtual-time.md) and
  // the whole oracle applies, timing included. Real: wall-clock worlds, the timing checks off.
  ClientTime time = ClientTime::real_time;
  vtime::ControllerOptions controller;   // virtual time: the shim, the watchdog
  std::optional<Micros> max_world;  // cut every world to this long (real time costs wall time)
  ClientBounds bounds;
  std::string log_dir;              // each client's output: <log_dir>/world-<i>-<vehicle>.log; "" → none
};

// The generated world as a client world: external clients, no misbehaviour switches (they
// drive the in-process client only), at most `max_world` long, and the client hazards.
scenario::Scenario for_external_client(scenario::Scenario world, std::uint64_t index, std::optional<Micros> max_world);

// What a client must survive that the product can send (client_hazards.cpp), drawn from the
// world's seed and added to its timeline and vehicles:
//   * ack_time_offset of 2^53 or more on every vehicle, in every even world and about half the
//     odd ones (bands above 2^53, above 2^63 and just below 2^64);
//   * a Streamer-side close of each vehicle's connection, a disconnect or a restart of its
//     listener (closed 200 ms–1.5 s), in every world of 10 s or more and half the shorter ones;
//   * client data from a plugin: client_user_data of up to 15 KiB of non-ASCII JSON (the
//     control frame close to its 16 KiB limit), and `controller: null` (ocp_disable_gamepad);
//   * an outage of the operator's messages past no_control_timeout: the default controller.
void add_client_hazards(scenario::Scenario& world, std::uint64_t index);
// Which of those a world holds, read off the world itself, by name: ack_time_above_2^53,
// streamer_close, listener_restart, user_data_over_8KiB, controller_null, control_path_fault.
std::vector<std::string> hazards_in(const scenario::Scenario& world);

// What ClientWatch allows a client in virtual time: no scheduling delays exist there, so an echo
// is current to the tick.
ClientBounds virtual_time_client_bounds();

// Runs one client world (already prepared by for_external_client). `stop` is polled (Ctrl-C).
// A client that cannot be started, or exits before it connects, is outcome.error.
WorldOutcome check_world_with_client(const scenario::Scenario& world, std::uint64_t index, const ClientRun& run,
                                     const std::function<bool()>& stop);

}  // namespace ocp::campaign
