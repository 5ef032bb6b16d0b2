// What each timeline action does to the World (timeline.hpp). Only public World / core calls:
// the scenario engine adds no hooks to the cores.
#include "timeline.hpp"

#include <algorithm>
#include <functional>
#include <memory>

#include "ocp/pipe.hpp"
#include "vehicle_client/misbehaviour.hpp"
#include "world_setup.hpp"

namespace ocp::scenario {
namespace {

// A ramp moves in steps this long: fine enough for latency_limit crossings at 10 ms ticks to
// land within one step of the straight line, coarse enough to cost nothing.
constexpr Micros ramp_step{100'000};

std::vector<LinkDirection*> directions(World& world, const std::string& vehicle, Direction direction) {
  ComChannel& link = world.link(vehicle);
  switch (direction) {
    case Direction::to_streamer: return {&link.to_streamer()};
    case Direction::to_player: return {&link.to_player()};
    case Direction::both: break;
  }
  return {&link.to_streamer(), &link.to_player()};
}

class Actions {
 public:
  // `end` is relative to `origin` (the executor's time when the run started).
  Actions(World& world, SimTime end, SimTime origin, OperatorClient* operator_client)
      : world_(world), executor_(world.executor()), end_(origin + end), origin_(origin), operator_client_(operator_client) {}

  void operator()(const SetImpairments& set) {
    for (LinkDirection* direction : directions(world_, set.vehicle, set.direction)) {
      const Impairments from = direction->impairments();
      const Impairments to = apply_patch(from, set.patch);
      if (set.ramp <= Micros{0}) {
        direction->set_impairments(to);
        continue;
      }
      const std::int64_t steps = std::max<std::int64_t>(1, (set.ramp.count() + ramp_step.count() - 1) / ramp_step.count());
      const SimTime start = executor_.now();
      for (std::int64_t k = 1; k <= steps; ++k) {
        const double fraction = static_cast<double>(k) / static_cast<double>(steps);
        const SimTime at = start + Micros{set.ramp.count() * k / steps};
        executor_.call_at(at, [direction, from, to, fraction] {
          direction->set_impairments(interpolate(from, to, fraction));
        });
      }
      // The first step at once, so the ramp starts moving where the event says.
      direction->set_impairments(interpolate(from, to, 0.0));
    }
  }
  void operator()(const LinkOutage& outage) {
    for (LinkDirection* direction : directions(world_, outage.vehicle, outage.direction)) {
      direction->outage_for(outage.duration);
    }
  }
  void operator()(const CameraStall& stall) {
    StreamerCore& streamer = world_.streamer(stall.vehicle);
    streamer.set_camera_stalled(stall.camera, stall.stalled);
    if (stall.stalled && stall.duration > Micros{0}) {
      executor_.call_after(stall.duration, [&streamer, camera = stall.camera] {
        streamer.set_camera_stalled(camera, false);
      });
    }
  }
  void operator()(const FrameLoopStall& stall) {
    world_.streamer(stall.vehicle).inject_frame_loop_stall(stall.duration);
  }
  void operator()(const ControlThreadStall& stall) {
    StreamerCore& streamer = world_.streamer(stall.vehicle);
    streamer.set_control_thread_stalled(true);
    executor_.call_after(stall.duration, [&streamer] { streamer.set_control_thread_stalled(false); });
  }
  void operator()(const DisconnectVehicle& disconnect) {
    if (disconnect.listener_down > Micros{0} || world_.vehicle_client(disconnect.vehicle) == nullptr) {
      world_.close_vehicle_connection(disconnect.vehicle, disconnect.listener_down);
    } else {
      world_.drop_vehicle_connection(disconnect.vehicle);
    }
  }
  void operator()(const SetMisbehaviour& set) {
    if (VehicleClient* client = world_.vehicle_client(set.vehicle)) client->set_misbehaviour(set.misbehave);
    if (set.second_connection) open_second_connection(set.vehicle);
  }
  // The far end stays open (kept here) until the run ends: only the Streamer may close it.
  void open_second_connection(const std::string& vehicle) {
    PipeOptions options;
    options.one_way_delay = world_.config().vehicle_pipe_delay;
    options.name_a = "pipe:second-client:" + vehicle;
    options.name_b = "pipe:streamer:" + vehicle;
    PipeEnds ends = make_pipe(executor_, options);
    second_connections_.push_back(std::move(ends.a));
    world_.accept_vehicle_connection(vehicle, std::move(ends.b));
  }
  void operator()(const SetOperatorMisbehaviour& set) {
    if (operator_client_ == nullptr) return;
    operator_client_->set_misbehaviour(set.misbehave);
    if (set.second_connection) operator_client_->open_second_connection();
  }
  void operator()(const GamepadAction& pad) {
    Gamepad& gamepad = world_.player().gamepad();
    switch (pad.kind) {
      case GamepadAction::Kind::unplug: gamepad.unplug(); return;
      case GamepadAction::Kind::replug: gamepad.replug(); return;
      case GamepadAction::Kind::script: apply_gamepad(gamepad, pad.script, executor_.now()); return;
    }
  }
  void operator()(const SelectVehicle& select) { world_.player().select_vehicle(select.vehicle); }
  void operator()(const ClientDataAction& data) {
    send_client_data(world_, data, operator_client_);
    if (data.every <= Micros{0}) return;
    const SimTime until = data.until ? origin_ + *data.until : end_;
    // A source that keeps sending (a plugin echoing every frame): reschedules itself.
    auto repeat = std::make_shared<std::function<void()>>();
    World* world = &world_;
    *repeat = [world, data, until, client = operator_client_, repeat_weak = std::weak_ptr(repeat)] {
      send_client_data(*world, data, client);
      Executor& executor = world->executor();
      if (executor.now() + data.every <= until) {
        if (auto next = repeat_weak.lock()) executor.call_after(data.every, *next);
      }
    };
    repeats_.push_back(repeat);
    if (executor_.now() + data.every <= until) executor_.call_after(data.every, *repeat);
  }

  // With an operator client, tcp client data goes through its connection (and stops while it
  // is disconnected), as the product's :4001 does; without one tcp stays an abstract source.
  static void send_client_data(World& world, const ClientDataAction& data, OperatorClient* operator_client) {
    PlayerCore& player = world.player();
    ClientOcpShared message;
    message.active_vehicle = data.active_vehicle;
    for (const auto& [vehicle, entry] : data.vehicles) {
      ClientVehicleEntry out;
      if (entry.user_data_json) out.user_data = RawJson{*entry.user_data_json};
      out.ocp_disable_gamepad = entry.disable_gamepad;
      if (entry.echo != ClientDataAction::Echo::none) {
        if (const auto pair = player.latest_sei(vehicle)) {
          out.ack_time_returned = pair->ack_time;
          out.ack_time_mac_returned = entry.echo == ClientDataAction::Echo::corrupt
                                          ? pair->ack_time_mac ^ corrupt_mac_mask
                                          : pair->ack_time_mac;
        }
      }
      message.client_user_data[vehicle] = out;
    }
    if (data.source == ClientSource::tcp && operator_client != nullptr) {
      operator_client->send_client_data(message);
      return;
    }
    player.handle_client_data(data.source, message);
  }

  std::vector<std::shared_ptr<std::function<void()>>> repeats_;   // keep repeating sources alive
  std::vector<std::shared_ptr<ByteStream>> second_connections_;   // second connections' far ends

 private:
  World& world_;
  Executor& executor_;
  SimTime end_;      // absolute
  SimTime origin_;
  OperatorClient* operator_client_;
};

}  // namespace

std::shared_ptr<void> schedule_timeline(World& world, const std::vector<TimelineEvent>& timeline, SimTime end,
                       std::vector<FiredEvent>& fired, SimTime origin, OperatorClient* operator_client) {
  auto actions = std::make_shared<Actions>(world, end, origin, operator_client);
  for (const TimelineEvent& event : timeline) {
    world.executor().call_at(origin + event.at, [actions, &event, &fired, &world, origin] {
      fired.push_back({world.executor().now() - origin, event.name, event.label});
      std::visit(*actions, event.action);
    });
  }
  return actions;
}

}  // namespace ocp::scenario
