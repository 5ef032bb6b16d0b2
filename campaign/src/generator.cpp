// The world generator (generator.hpp). Every disturbance is an episode with an end: an
// impairment step is followed by a step back to the start settings, a misbehaviour by "all
// off", an unplug by a replug; outages and stalls carry their own duration. All episodes end
// before duration − liveness_bound, so the oracle's liveness check has room to look.
#include "campaign/generator.hpp"

#include <algorithm>
#include <cmath>

#include "campaign/world_facts.hpp"
#include "draw.hpp"
#include "world/seeds.hpp"

namespace ocp::campaign {

std::uint64_t world_seed(std::uint64_t campaign_seed, std::uint64_t index) {
  return derive_seed(campaign_seed, "world:" + std::to_string(index));
}

namespace {

using namespace scenario;

constexpr Micros first_episode_at{500'000};
constexpr Micros longest_stall{2'000'000};   // frame-loop and control-thread stalls
constexpr std::uint64_t large_ack_offset = (std::uint64_t{1} << 53) + 12345;

Impairments base_link(Draw& draw, const Profile& profile) {
  Impairments link;
  link.delay = draw.duration(profile.base_delay);
  link.jitter = draw.duration(profile.base_jitter);
  link.jitter_kind = link.jitter > Micros{0} ? Impairments::JitterKind::uniform : Impairments::JitterKind::none;
  link.loss_probability = Draw::tidy(draw.number(profile.base_loss));
  return link;
}

VehicleSpec vehicle(Draw& draw, const Profile& profile, int index, bool monitor) {
  VehicleSpec spec;
  spec.name = "v" + std::to_string(index + 1);
  spec.monitor = monitor;
  StreamerConfig& s = spec.streamer;
  s.latency_limit = draw.duration(profile.latency_limit);
  s.no_control_timeout = draw.duration(profile.no_control_timeout);
  s.vehicle_read_timeout = draw.duration(profile.vehicle_read_timeout);
  s.camera_drop_timeout = draw.duration(profile.camera_drop_timeout);
  s.streamer_slow_threshold = draw.duration(profile.streamer_slow_threshold);
  s.control_queue_limit = static_cast<std::size_t>(std::lround(draw.number(profile.control_queue_limit)));
  s.control_queue_max_age = draw.duration(profile.control_queue_max_age);
  // Sometimes above 2^53, where an ack_time read through a double breaks (SPEC §2).
  if (draw.chance(0.2)) s.ack_time_offset = large_ack_offset;
  s.cameras.clear();
  const int cameras = draw.integer(profile.cameras_min, profile.cameras_max);
  for (int c = 0; c < cameras; ++c) {
    CameraConfig camera;
    camera.name = "cam" + std::to_string(c + 1);
    camera.fps = std::round(draw.number(profile.camera_fps));
    camera.drop_detector = draw.chance(0.8);
    s.cameras.push_back(camera);
  }
  spec.to_streamer = base_link(draw, profile);
  spec.to_player = base_link(draw, profile);
  return spec;
}

class TimelineBuilder {
 public:
  TimelineBuilder(Draw& draw, const Profile& profile, Scenario& scenario)
      : draw_(draw), profile_(profile), scenario_(scenario) {
    for (const VehicleSpec& spec : scenario.world.vehicles) {
      all_.push_back(&spec);
      if (!spec.monitor) control_.push_back(&spec);
    }
  }

  void add(ActionKind kind, SimTime at, SimTime latest_end) {
    const Micros length = std::min(draw_.duration(profile_.episode), latest_end - at);
    if (length <= Micros{0}) return;
    const SimTime end = at + length;
    const VehicleSpec& any = *draw_.pick(all_);
    const VehicleSpec& control = *draw_.pick(control_);
    switch (kind) {
      case ActionKind::impair: impair(any, at, end); return;
      case ActionKind::latency_ramp: latency_ramp(control, at, end); return;
      case ActionKind::outage:
        push(at, LinkOutage{any.name, direction(), length});
        return;
      case ActionKind::burst_loss: burst_loss(any, at, end); return;
      case ActionKind::camera_stall: {
        std::vector<std::string> cameras;
        for (const CameraConfig& camera : any.streamer.cameras) cameras.push_back(camera.name);
        push(at, CameraStall{any.name, draw_.pick(cameras), true, length});
        return;
      }
      case ActionKind::frame_loop_stall:
        push(at, FrameLoopStall{any.name, std::min(length, longest_stall)});
        return;
      case ActionKind::control_thread_stall:
        push(at, ControlThreadStall{any.name, std::min(length, longest_stall)});
        return;
      case ActionKind::disconnect: push(at, DisconnectVehicle{any.name}); return;
      case ActionKind::misbehave: misbehave(control, at, end); return;
      case ActionKind::gamepad_unplug:
        push(at, GamepadAction{GamepadAction::Kind::unplug, {}});
        push(end, GamepadAction{GamepadAction::Kind::replug, {}});
        return;
      case ActionKind::client_data: client_data(at, end); return;
      case ActionKind::select_vehicle: select(at); return;
      case ActionKind::operator_misbehave: operator_misbehave(at, end); return;
    }
  }

 private:
  Direction direction() {
    static const std::vector<Direction> all = {Direction::both, Direction::to_streamer, Direction::to_player};
    return draw_.pick(all);
  }
  void push(SimTime at, Action action) { scenario_.timeline.push_back({at, "", "", {}, std::move(action)}); }

  // A step of some of the link's settings, then back to where the link started.
  void impair(const VehicleSpec& spec, SimTime at, SimTime end) {
    ImpairmentPatch on, off;
    const Impairments& base = spec.to_streamer;
    const int fields = draw_.integer(1, 3);
    for (int f = 0; f < fields; ++f) {
      switch (draw_.integer(0, 5)) {
        case 0:
          on.delay = draw_.duration(profile_.delay);
          off.delay = base.delay;
          break;
        case 1:
          on.jitter = draw_.duration(profile_.jitter);
          on.jitter_kind = draw_.chance(0.5) ? Impairments::JitterKind::uniform : Impairments::JitterKind::normal;
          off.jitter = base.jitter;
          off.jitter_kind = base.jitter_kind;
          break;
        case 2:
          on.loss = Draw::tidy(draw_.number(profile_.loss));
          off.loss = base.loss_probability;
          break;
        case 3:
          on.duplicate = Draw::tidy(draw_.number(profile_.duplicate));
          off.duplicate = 0.0;
          break;
        case 4:
          on.reorder = Draw::tidy(draw_.number(profile_.reorder));
          on.reorder_extra_delay = draw_.duration(profile_.reorder_extra_delay);
          off.reorder = 0.0;
          off.reorder_extra_delay = Micros{0};
          break;
        default: {
          // A bandwidth cap always comes with a queue of at most one second of it, so a link
          // never holds back more than a second once the cap is lifted (world_facts.cpp).
          const double bps = std::round(draw_.number(profile_.bandwidth_bps));
          const double queue = std::min(draw_.number(profile_.queue_limit_bytes), bps / 8.0);
          on.bandwidth_bps = bps;
          on.queue_limit_bytes = static_cast<std::size_t>(std::max(100.0, std::round(queue)));
          off.bandwidth_bps = 0.0;
          off.queue_limit_bytes = 0;
          break;
        }
      }
    }
    const Direction way = direction();
    push(at, SetImpairments{spec.name, way, on, Micros{0}});
    push(end, SetImpairments{spec.name, way, off, Micros{0}});
  }

  // Delay ramped across the vehicle's latency_limit (a round trip is two one-way delays).
  void latency_ramp(const VehicleSpec& spec, SimTime at, SimTime end) {
    const Micros limit = spec.streamer.latency_limit;
    ImpairmentPatch up, down;
    up.delay = Micros{(limit.count() * draw_.integer(3, 12) / 10 / 2) / 1000 * 1000};
    down.delay = spec.to_streamer.delay;
    const Micros ramp{((end - at).count() / 2) / 1000 * 1000};
    push(at, SetImpairments{spec.name, Direction::both, up, ramp});
    push(end, SetImpairments{spec.name, Direction::both, down, Micros{0}});
  }

  void burst_loss(const VehicleSpec& spec, SimTime at, SimTime end) {
    ImpairmentPatch on, off;
    on.burst_loss = true;
    on.good_to_bad = Draw::tidy(draw_.number(0.01, 0.3));
    on.bad_to_good = Draw::tidy(draw_.number(0.05, 0.5));
    on.loss_in_good = 0.0;
    on.loss_in_bad = Draw::tidy(draw_.number(0.5, 1.0));
    off.burst_loss = false;
    const Direction way = direction();
    push(at, SetImpairments{spec.name, way, on, Micros{0}});
    push(end, SetImpairments{spec.name, way, off, Micros{0}});
  }

  static constexpr BadResponse generated_bad_responses[] = {BadResponse::missing_field, BadResponse::wrong_type,
                                                            BadResponse::not_an_object, BadResponse::ack_time_out_of_range,
                                                            BadResponse::eof_mid_frame};

  // Every misbehaviour the scenario format has: the switches, each kind of broken response
  // (SPEC §2: the Streamer closes the connection) and a second connection (SPEC §3.1: refused).
  void misbehave(const VehicleSpec& spec, SimTime at, SimTime end) {
    Misbehaviour on;
    bool second_connection = false;
    switch (draw_.integer(0, 8)) {
      case 0: on.stop_echo = true; break;
      case 1: on.corrupt_mac = true; break;
      case 2: on.delay_responses = draw_.duration(Micros{50'000}, Micros{800'000}); break;
      case 3: on.oversized_frames = true; break;
      case 4: on.ack_through_double = true; break;
      case 5: on.malformed_json = true; break;
      case 6: on.bad_response = generated_bad_responses[static_cast<std::size_t>(draw_.integer(0, 4))]; break;
      case 7: second_connection = true; break;
      default: on.silent = true; break;
    }
    push(at, SetMisbehaviour{spec.name, on, second_connection});
    push(end, SetMisbehaviour{spec.name, Misbehaviour{}});
  }

  // Every misbehaviour of the operator port (SPEC §2, §4.2): the Player closes the connection
  // for a broken frame or silence, drains an oversized one, and refuses a second connection.
  void operator_misbehave(SimTime at, SimTime end) {
    if (!scenario_.operator_client.connect) return;
    SetOperatorMisbehaviour on;
    switch (draw_.integer(0, 6)) {
      case 0: on.misbehave.malformed_json = true; break;
      case 1: on.misbehave.oversized_frames = true; break;
      case 2: on.misbehave.bad_message = BadClientMessage::not_an_object; break;
      case 3: on.misbehave.bad_message = BadClientMessage::wrong_type; break;
      case 4: on.misbehave.bad_message = BadClientMessage::eof_mid_frame; break;
      case 5: on.second_connection = true; break;
      default: on.misbehave.silent = true; break;
    }
    push(at, on);
    push(end, SetOperatorMisbehaviour{});
  }

  // A plugin takes the latency loop over (echoing every frame to the end), and sometimes the
  // web view sends client data too: a conflict, which stops client data until restart (§4.3).
  void client_data(SimTime at, SimTime end) {
    ClientDataAction plugin;
    plugin.source = ClientSource::plugin;
    for (const VehicleSpec* spec : control_) {
      ClientDataAction::Entry entry;
      entry.user_data_json = "{\"mode\":" + std::to_string(draw_.integer(0, 9)) + "}";
      entry.echo = ClientDataAction::Echo::latest;
      plugin.vehicles[spec->name] = entry;
    }
    plugin.every = Micros{10'000};
    push(at, plugin);
    if (draw_.chance(0.3)) {
      ClientDataAction webview;
      webview.source = ClientSource::webview;
      ClientDataAction::Entry entry;
      entry.user_data_json = "{\"conflict\":true}";
      webview.vehicles[control_.front()->name] = entry;
      push(end, webview);
    }
  }

  void select(SimTime at) {
    if (control_.size() < 2) return;
    SelectVehicle select;
    if (!draw_.chance(0.1)) select.vehicle = draw_.pick(control_)->name;
    push(at, select);
  }

  Draw& draw_;
  const Profile& profile_;
  Scenario& scenario_;
  std::vector<const VehicleSpec*> all_, control_;
};

ActionKind weighted_kind(Draw& draw, const Profile& profile) {
  double total = 0;
  for (const auto& [kind, weight] : profile.weights) total += weight;
  double x = draw.unit() * total;
  for (const auto& [kind, weight] : profile.weights) {
    if (x < weight) return kind;
    x -= weight;
  }
  return ActionKind::impair;
}

}  // namespace

Scenario generate_world(const Profile& profile, std::uint64_t campaign_seed, std::uint64_t index) {
  Scenario scenario;
  scenario.seed = world_seed(campaign_seed, index);
  scenario.name = "world-" + std::to_string(index);
  scenario.description = "campaign " + std::to_string(campaign_seed) + ", profile " + profile.name + ", world " +
                         std::to_string(index);
  Draw draw(scenario.seed);
  scenario.duration = draw.duration(profile.duration);
  const int vehicles = draw.integer(profile.vehicles_min, profile.vehicles_max);
  for (int v = 0; v < vehicles; ++v) {
    scenario.world.vehicles.push_back(vehicle(draw, profile, v, v > 0 && draw.chance(profile.monitor_share)));
  }
  scenario.world.player.fleet = vehicles > 1;
  scenario.world.player.no_feedback_timeout = draw.duration(profile.no_feedback_timeout);
  scenario.world.reconnect_backoff = draw.duration(profile.reconnect_backoff);
  if (draw.chance(profile.operator_client_share)) {
    OperatorClientSetting& client = scenario.operator_client;
    client.connect = true;
    client.keep_alive_period = draw.duration(profile.operator_keep_alive_period);
    client.reconnect_backoff = draw.duration(profile.reconnect_backoff);
  }
  // The built-in drive script: the controller is not the default one, so a control frame that
  // should carry the default controller but does not is visible.
  scenario.gamepad.kind = GamepadScriptSetting::Kind::drive;

  TimelineBuilder timeline(draw, profile, scenario);
  int control_vehicles = 0;
  for (const VehicleSpec& spec : scenario.world.vehicles) control_vehicles += spec.monitor ? 0 : 1;
  // A fleet starts with no vehicle selected (everyone VehicleControlInactive): select one first.
  if (control_vehicles >= 2) {
    SelectVehicle first;
    first.vehicle = "v1";
    scenario.timeline.push_back({SimTime{0}, "", "", {}, first});
  }
  // Every episode ends before the liveness window. The bound grows with the largest delay a
  // link is ever given, so it is taken here with the largest delay the profile can draw.
  const Micros largest_episode_delay =
      std::max(profile.delay.max + profile.jitter.max + profile.reorder_extra_delay.max,
               Micros{profile.latency_limit.max.count() * 12 / 10 / 2});
  const SimTime latest_end = scenario.duration - liveness_bound(scenario) - 2 * largest_episode_delay;
  const int events = draw.integer(profile.events_min, profile.events_max);
  for (int e = 0; e < events; ++e) {
    const ActionKind kind = weighted_kind(draw, profile);
    if (latest_end <= first_episode_at + Micros{10'000}) break;
    const SimTime at = draw.duration(first_episode_at, latest_end - Micros{10'000});
    timeline.add(kind, at, latest_end);
  }
  std::stable_sort(scenario.timeline.begin(), scenario.timeline.end(),
                   [](const TimelineEvent& a, const TimelineEvent& b) { return a.at < b.at; });
  for (TimelineEvent& event : scenario.timeline) event.label = "generated";
  return scenario;
}

}  // namespace ocp::campaign
