#pragma once
// A generator profile (campaign/profiles/*.yaml, docs/campaigns.md): the ranges every drawn
// value lies in, and the weights of the timeline actions. Loading checks every key and range;
// a mistake is a ProfileError that says file:line:column and why (exit 2).
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>

#include "ocp/time.hpp"

namespace ocp::campaign {

class ProfileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;   // the message is "file:line:column: reason"
};

struct DurationRange {
  Micros min{0}, max{0};
};
struct NumberRange {
  double min = 0.0, max = 0.0;
};

// The timeline actions a world may draw, in the order of docs/campaigns.md.
enum class ActionKind {
  impair,                // a step of delay/jitter/loss/duplication/reordering/bandwidth, then back
  latency_ramp,          // a ramp of delay across latency_limit, then back
  outage,
  burst_loss,            // Gilbert–Elliott burst loss, then off
  camera_stall,
  frame_loop_stall,
  control_thread_stall,
  disconnect,
  misbehave,             // one misbehaviour switched on, then all off
  gamepad_unplug,        // unplug, then replug
  client_data,           // a client-data source appears (and sometimes a second one conflicts)
  select_vehicle,        // active-vehicle switch (fleets with two control vehicles or more)
  operator_misbehave,    // one misbehaviour on the Player's :4001 port, then all off (worlds with an operator client)
};
inline constexpr int action_kind_count = 13;
std::string_view action_kind_name(ActionKind kind);

struct Profile {
  std::string name;          // the file's stem: "default", "calm"
  std::uint64_t digest = 0;  // of the file's text: shards of other profiles are refused
  DurationRange duration{Micros{10'000'000}, Micros{120'000'000}};
  int vehicles_min = 1, vehicles_max = 4;
  double monitor_share = 0.25;   // each vehicle after the first is a monitor with this chance
  double operator_client_share = 0.5;   // a world connects an operator client to :4001 with this chance
  int cameras_min = 1, cameras_max = 3;
  NumberRange camera_fps{10, 60};
  // SPEC §8 timers.
  DurationRange latency_limit{Micros{200'000}, Micros{1'000'000}};
  DurationRange no_control_timeout{Micros{500'000}, Micros{2'000'000}};
  DurationRange vehicle_read_timeout{Micros{1'000'000}, Micros{3'000'000}};
  DurationRange camera_drop_timeout{Micros{100'000}, Micros{500'000}};
  DurationRange streamer_slow_threshold{Micros{300'000}, Micros{1'000'000}};
  NumberRange control_queue_limit{10, 50};
  DurationRange control_queue_max_age{Micros{50'000}, Micros{200'000}};
  DurationRange no_feedback_timeout{Micros{500'000}, Micros{2'000'000}};
  DurationRange reconnect_backoff{Micros{50'000}, Micros{500'000}};   // vehicle and operator clients
  DurationRange operator_keep_alive_period{Micros{100'000}, Micros{1'000'000}};   // < the 2 s :4001 read timeout
  // The links' settings at start (every world).
  DurationRange base_delay{Micros{0}, Micros{30'000}};
  DurationRange base_jitter{Micros{0}, Micros{5'000}};
  NumberRange base_loss{0, 0.01};
  // Episodes on the timeline.
  int events_min = 1, events_max = 10;   // episodes per world
  DurationRange episode{Micros{200'000}, Micros{4'000'000}};
  DurationRange delay{Micros{0}, Micros{600'000}};
  DurationRange jitter{Micros{0}, Micros{80'000}};
  NumberRange loss{0, 0.4};
  NumberRange duplicate{0, 0.2};
  NumberRange reorder{0, 0.3};
  DurationRange reorder_extra_delay{Micros{0}, Micros{80'000}};
  NumberRange bandwidth_bps{50'000, 2'000'000};
  NumberRange queue_limit_bytes{4'000, 200'000};
  std::map<ActionKind, double> weights;   // every kind; 0 = never drawn
  double determinism_share = 0.05;        // worlds run twice for the trace digest
};

// Reads and checks a profile file. Throws ProfileError.
Profile load_profile(const std::string& path);
Profile parse_profile(const std::string& text, const std::string& path);

// The path of a shipped profile: share/ocp-sim/campaign/profiles/NAME.yaml, found at run time
// (sim_app/data_dir.hpp). Throws ProfileError, naming where it looked, when the data is missing.
std::string shipped_profile_path(const std::string& name);

}  // namespace ocp::campaign
