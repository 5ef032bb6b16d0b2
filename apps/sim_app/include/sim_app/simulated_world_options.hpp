#pragma once
// The settings both simulators give their simulated world, filled from the shared command-line
// options (CommonOptions::world_options). StreamerSimOptions and PlayerSimOptions extend it.
#include <cstdint>
#include <memory>
#include <vector>

#include "ocp/com_channel.hpp"
#include "sim_app/plugin_params.hpp"
#include "sim_app/gamepad_script.hpp"
#include "streamer/streamer_core.hpp"

namespace ocp::sim_app {

struct SimulatedWorldOptions {
  PluginParams plugin_params;            // the TCP port, ocp_tcp_allow_remote, latency_limit
  std::vector<CameraConfig> cameras;     // per vehicle; empty: the StreamerConfig default (front, 30 fps)
  Impairments link;                      // both directions of every fake com channel
  std::uint64_t seed = 1;
  GamepadScript gamepad;                 // the operator station's gamepad (default: drive)
  std::uint64_t ack_time_offset = 0;     // added to every ack_time of every Streamer (SPEC §5)
  // Trace-driven capacity per direction (--link-trace-up/-down); null: `link` alone.
  // Up is the vehicle's uplink (video, feedback: to_player); down is to_streamer.
  std::shared_ptr<const DeliveryTrace> link_trace_up = nullptr;
  std::shared_ptr<const DeliveryTrace> link_trace_down = nullptr;

  Impairments to_player() const { return with_trace(link_trace_up); }
  Impairments to_streamer() const { return with_trace(link_trace_down); }

 private:
  Impairments with_trace(const std::shared_ptr<const DeliveryTrace>& trace) const {
    Impairments direction = link;
    direction.trace = trace;
    return direction;
  }
};

}  // namespace ocp::sim_app
