// Facts about a world read off its model (world_facts.hpp).
#include "campaign/world_facts.hpp"

#include <algorithm>

namespace ocp::campaign {

namespace {
constexpr Micros queue_allowance{1'000'000};   // the generator keeps a bandwidth queue ≤ 1 s
constexpr Micros margin{500'000};

Micros effect_length(const scenario::Scenario& scenario, const scenario::Action& action) {
  using namespace scenario;
  if (const auto* set = std::get_if<SetImpairments>(&action)) return set->ramp;
  if (const auto* outage = std::get_if<LinkOutage>(&action)) return outage->duration;
  if (const auto* stall = std::get_if<CameraStall>(&action)) return stall->stalled ? stall->duration : Micros{0};
  if (const auto* stall = std::get_if<FrameLoopStall>(&action)) return stall->duration;
  if (const auto* stall = std::get_if<ControlThreadStall>(&action)) return stall->duration;
  if (const auto* disconnect = std::get_if<DisconnectVehicle>(&action)) {
    return disconnect->listener_down + scenario.world.reconnect_backoff;
  }
  return Micros{0};
}
}  // namespace

Micros largest_delay(const scenario::Scenario& scenario) {
  Micros largest{0};
  for (const VehicleSpec& spec : scenario.world.vehicles) {
    largest = std::max({largest, spec.to_streamer.delay + spec.to_streamer.jitter + spec.to_streamer.reorder_extra_delay,
                        spec.to_player.delay + spec.to_player.jitter + spec.to_player.reorder_extra_delay});
  }
  for (const scenario::TimelineEvent& event : scenario.timeline) {
    if (const auto* set = std::get_if<scenario::SetImpairments>(&event.action)) {
      const auto& p = set->patch;
      largest = std::max(largest, p.delay.value_or(Micros{0}) + p.jitter.value_or(Micros{0}) +
                                      p.reorder_extra_delay.value_or(Micros{0}));
    }
  }
  return largest;
}

Micros liveness_bound(const scenario::Scenario& scenario) {
  Micros read_timeout{0};
  double slowest_fps = 1000.0;
  for (const VehicleSpec& spec : scenario.world.vehicles) {
    read_timeout = std::max(read_timeout, spec.streamer.vehicle_read_timeout);
    slowest_fps = std::min(slowest_fps, spec.streamer.frame_rate_hz);
    for (const CameraConfig& camera : spec.streamer.cameras) slowest_fps = std::min(slowest_fps, camera.fps);
  }
  const Micros frame{static_cast<std::int64_t>(1e6 / std::max(slowest_fps, 0.1))};
  const Micros vehicle_side = scenario.world.reconnect_backoff + read_timeout + 2 * largest_delay(scenario) +
                              queue_allowance + 2 * frame + margin;
  if (!scenario.operator_client.connect) return vehicle_side;
  // The operator client is back: a silent second connection holding :4001 times out, then the
  // client reconnects after its backoff and sends its first keep-alive.
  const scenario::OperatorClientSetting& client = scenario.operator_client;
  return std::max(vehicle_side, scenario.world.player.client_read_timeout + client.reconnect_backoff +
                                    client.keep_alive_period + margin);
}

SimTime quiet_point(const scenario::Scenario& scenario) {
  SimTime quiet{0};
  for (const scenario::TimelineEvent& event : scenario.timeline) {
    quiet = std::max(quiet, event.at + effect_length(scenario, event.action));
  }
  for (const VehicleSpec& spec : scenario.world.vehicles) {   // queued frame-loop stalls end later
    for (const Window& stall : frame_loop_stalls(scenario, spec.name)) quiet = std::max(quiet, stall.end);
  }
  return quiet;
}

std::vector<Window> control_thread_stalls(const scenario::Scenario& scenario, const std::string& vehicle) {
  std::vector<Window> out;
  for (const auto& event : scenario.timeline) {
    if (const auto* stall = std::get_if<scenario::ControlThreadStall>(&event.action); stall && stall->vehicle == vehicle) {
      out.push_back({event.at, event.at + stall->duration});
    }
  }
  return out;
}

// A stall blocks the loop's next iteration (streamer_sim/core/frame_loop.hpp): one injected while
// another blocks the loop runs after it, so the windows queue up. (Of two injected before the same
// iteration the core runs only the later; the queued window then covers more than the stall did,
// which only widens where StreamerSlow may be active.)
std::vector<Window> frame_loop_stalls(const scenario::Scenario& scenario, const std::string& vehicle) {
  std::vector<Window> out;
  for (const auto& event : scenario.timeline) {
    if (const auto* stall = std::get_if<scenario::FrameLoopStall>(&event.action); stall && stall->vehicle == vehicle) {
      const SimTime start = out.empty() ? event.at : std::max(event.at, out.back().end);
      out.push_back({start, start + stall->duration});
    }
  }
  return out;
}

std::vector<Window> camera_stalls(const scenario::Scenario& scenario, const std::string& vehicle,
                                  const std::string& camera) {
  std::vector<Window> out;
  std::optional<SimTime> open;
  for (const auto& event : scenario.timeline) {
    const auto* stall = std::get_if<scenario::CameraStall>(&event.action);
    if (stall == nullptr || stall->vehicle != vehicle || stall->camera != camera) continue;
    if (stall->stalled && stall->duration > Micros{0}) {
      out.push_back({event.at, event.at + stall->duration});
    } else if (stall->stalled) {
      if (!open) open = event.at;
    } else if (open) {
      out.push_back({*open, event.at});
      open.reset();
    }
  }
  if (open) out.push_back({*open, scenario.duration + Micros{1}});
  return out;
}

}  // namespace ocp::campaign
