// What every client world adds to its generated world (client_world.hpp, add_client_hazards):
// the product's legal extremes that a vehicle client must survive, drawn from the world's seed
// so that a world stays a pure function of its seed and index.
#include <algorithm>
#include <string>
#include <string_view>

#include "campaign/client_world.hpp"
#include "draw.hpp"
#include "world/seeds.hpp"

namespace ocp::campaign {

namespace {

using namespace scenario;

constexpr Micros first_hazard_at{1'500'000};          // the client has connected by then
constexpr Micros every_world_closes_from{10'000'000};   // a world this long always gets a close
constexpr Micros longest_listener_down{1'500'000};
// After a close: ClientWatch's reconnect bound (5 s) and a second to see the new connection.
constexpr Micros reconnect_room{6'000'000};

// Three bands, each 2^40 µs wide: just above 2^53 (a double rounds), above 2^63 (a signed
// 64-bit integer overflows) and just below 2^64 (the largest u64 the product sends).
std::uint64_t high_ack_offset(Draw& draw) {
  constexpr std::uint64_t span = std::uint64_t{1} << 40;
  constexpr std::uint64_t band_starts[] = {std::uint64_t{1} << 53, std::uint64_t{1} << 63, ~std::uint64_t{0} - 2 * span};
  const std::uint64_t start = band_starts[draw.integer(0, 2)];
  return start + static_cast<std::uint64_t>(draw.unit() * static_cast<double>(span));
}

// About `bytes` of JSON text with 2-, 3- and 4-byte UTF-8, escapes, a null and numbers, as a
// Player may pass through as client_user_data.
std::string user_data_json(Draw& draw, std::size_t bytes) {
  static constexpr std::string_view pieces[] = {"Grüße ", "東京 ", "✓ ", "🚚 ", "\\\"quoted\\\" ", "tab\\t ", "plain ascii "};
  std::string text;
  while (text.size() < bytes) text += pieces[draw.integer(0, 6)];
  return R"({"note":")" + text + R"(","nothing":null,"numbers":[0,-1.5,1e3,18446744073709551615],"nested":{"ok":true}})";
}

class Hazards {
 public:
  Hazards(Scenario& world, Draw& draw) : world_(world), draw_(draw) {}

  void ack_offsets(bool high) {
    if (!high) return;
    for (VehicleSpec& spec : world_.world.vehicles) spec.streamer.ack_time_offset = high_ack_offset(draw_);
  }

  // One Streamer-side close per vehicle: a disconnect, or a restart of its listener.
  void closes() {
    const bool always = world_.duration >= every_world_closes_from;
    for (const VehicleSpec& spec : world_.world.vehicles) {
      if (!always && !draw_.chance(0.5)) continue;
      DisconnectVehicle close{spec.name};
      if (draw_.chance(0.5)) close.listener_down = draw_.duration(Micros{200'000}, longest_listener_down);
      const SimTime latest = world_.duration - reconnect_room - close.listener_down;
      if (latest < first_hazard_at) continue;
      push(draw_.duration(first_hazard_at, latest), close);
    }
  }

  // Client data from a plugin for a while: user data up to the frame limit, and sometimes the
  // gamepad disabled (controller: null).
  void client_data() {
    const SimTime latest_start = world_.duration / 2;
    if (latest_start <= first_hazard_at) return;
    ClientDataAction data;
    data.source = ClientSource::plugin;
    data.every = Micros{10'000};
    for (const VehicleSpec& spec : world_.world.vehicles) {
      if (spec.monitor) continue;
      ClientDataAction::Entry entry;
      // Large: the control frame comes close to the 16 KiB limit (the rest of it is < 1 KiB).
      const std::size_t bytes = draw_.chance(0.6) ? static_cast<std::size_t>(draw_.integer(11 * 1024, 15 * 1024))
                                                  : static_cast<std::size_t>(draw_.integer(0, 2048));
      entry.user_data_json = user_data_json(draw_, bytes);
      if (draw_.chance(0.5)) entry.disable_gamepad = true;
      entry.echo = ClientDataAction::Echo::latest;
      data.vehicles[spec.name] = entry;
    }
    if (data.vehicles.empty()) return;
    const SimTime at = draw_.duration(first_hazard_at, latest_start);
    data.until = std::min(world_.duration - Micros{1'000'000}, at + draw_.duration(Micros{2'000'000}, world_.duration / 2));
    push(at, data);
    // Then the plugin goes on returning the pair to the end, without user data, as a plugin
    // does. Silent, it would stay the locked source with no pair returned (SPEC §4.3: no
    // self-echo after a lock): the latency loop open for good, HighLatency up to the end, and
    // every such world a liveness failure that says nothing about the vehicle client.
    ClientDataAction keep_echoing = data;
    keep_echoing.until.reset();
    for (auto& [vehicle, entry] : keep_echoing.vehicles) {
      entry = {};
      entry.echo = ClientDataAction::Echo::latest;
    }
    push(*data.until, keep_echoing);
  }

  // A control-path fault, so control frames carry the default controller for a while: the
  // operator's messages stop for longer than no_control_timeout.
  void control_fault() {
    std::vector<const VehicleSpec*> control;
    for (const VehicleSpec& spec : world_.world.vehicles) {
      if (!spec.monitor) control.push_back(&spec);
    }
    if (control.empty()) return;
    const VehicleSpec& spec = *draw_.pick(control);
    const Micros length = spec.streamer.no_control_timeout + draw_.duration(Micros{200'000}, Micros{1'000'000});
    const SimTime latest = world_.duration - length - Micros{2'000'000};
    if (latest < first_hazard_at) return;
    push(draw_.duration(first_hazard_at, latest), LinkOutage{spec.name, Direction::to_streamer, length});
  }

 private:
  void push(SimTime at, Action action) { world_.timeline.push_back({at, "", "client hazard", {}, std::move(action)}); }

  Scenario& world_;
  Draw& draw_;
};

}  // namespace

std::vector<std::string> hazards_in(const Scenario& world) {
  constexpr std::uint64_t two_to_53 = std::uint64_t{1} << 53;
  constexpr std::size_t large_user_data = 8 * 1024;
  bool high = false, close = false, restart = false, large = false, null_controller = false, control_fault = false;
  for (const VehicleSpec& spec : world.world.vehicles) high = high || spec.streamer.ack_time_offset >= two_to_53;
  for (const TimelineEvent& event : world.timeline) {
    if (const auto* disconnect = std::get_if<DisconnectVehicle>(&event.action)) {
      close = true;
      restart = restart || disconnect->listener_down > Micros{0};
    } else if (const auto* data = std::get_if<ClientDataAction>(&event.action)) {
      for (const auto& [vehicle, entry] : data->vehicles) {
        large = large || (entry.user_data_json && entry.user_data_json->size() >= large_user_data);
        null_controller = null_controller || entry.disable_gamepad.value_or(false);
      }
    } else if (const auto* outage = std::get_if<LinkOutage>(&event.action); outage && outage->direction != Direction::to_player) {
      for (const VehicleSpec& spec : world.world.vehicles) {
        control_fault = control_fault || (spec.name == outage->vehicle && outage->duration > spec.streamer.no_control_timeout);
      }
    }
  }
  std::vector<std::string> names;
  const std::pair<bool, const char*> all[] = {{high, "ack_time_above_2^53"},     {close, "streamer_close"},
                                              {restart, "listener_restart"},      {large, "user_data_over_8KiB"},
                                              {null_controller, "controller_null"}, {control_fault, "control_path_fault"}};
  for (const auto& [held, name] : all) {
    if (held) names.emplace_back(name);
  }
  return names;
}

void add_client_hazards(Scenario& world, std::uint64_t index) {
  Draw draw(derive_seed(world.seed, "client-hazards"));
  Hazards hazards(world, draw);
  // Every even world and about half the odd ones: at least half of any run of worlds.
  hazards.ack_offsets(index % 2 == 0 || draw.chance(0.5));
  hazards.closes();
  hazards.client_data();
  hazards.control_fault();
  std::stable_sort(world.timeline.begin(), world.timeline.end(),
                   [](const TimelineEvent& a, const TimelineEvent& b) { return a.at < b.at; });
}

}  // namespace ocp::campaign
