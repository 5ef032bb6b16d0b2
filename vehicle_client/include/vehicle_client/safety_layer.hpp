#pragma once
// The vehicle's own safety layer (SPEC §10). OCP is transport, not the safety controller, so
// the reference vehicle enforces its own rules on every command before it reaches an actuator:
//
//   1. Command watchdog   — no fresh control message for `watchdog` → safe state.
//   2. Fault mapping      — telemetry.fault, or the default (safe) controller that the Streamer
//                           substitutes during control-path faults → safe state. Decided on
//                           the boolean and the structured controller only; display strings
//                           (fault_reason) are never parsed. An untouched gamepad is the
//                           default controller too, so it brakes, but only a fault (flag,
//                           watchdog) disables driving.
//   3. Actuator limits    — magnitude caps and rate limits on throttle, brake and steering.
//   4. Drive interlock    — starts disabled; the start button (or {"enable": true} in user
//                           data) enables only with neutral sticks and no active fault; the
//                           back button, {"enable": false} or any fault disables again.
//   5. Command source     — `controller: null` uses commands from client_user_data
//                           ({"throttle":0..1, "brake":0..1, "steer":-1..1, "enable":bool});
//                           with neither → safe state.
//   6. Safe-state output  — throttle cut at once, brake ramped to `safe_brake`, steering held.
//
// Pure: no clock, no I/O; allocates only to parse user-data commands (controller null).
// Inputs are the decoded control message plus `now`; the output is recomputed by
// `evaluate(now)`. Call order:
//   on_control_message(message, now)  each time one arrives (cheap; never blocks);
//   evaluate(now)                     at the actuator rate (and after each message if wanted).
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ocp/messages.hpp"
#include "ocp/time.hpp"

namespace ocp {

// Normalised actuator command: throttle and brake in [0, 1], steer in [-1, 1] (fraction of the
// vehicle's maximum steering angle; positive = left).
struct ActuatorCommand {
  double throttle = 0.0;
  double brake = 0.0;
  double steer = 0.0;
  bool operator==(const ActuatorCommand&) const = default;
};

enum class DriveState : std::uint8_t {
  disabled,  // parked: actuators held in the safe state until the operator enables
  enabled,   // operator commands pass through (still subject to limits and faults)
};
std::string_view drive_state_name(DriveState state);  // "disabled" | "enabled"

// Why the output is in the safe state. Several may hold at once.
enum class SafetyReason : std::uint8_t {
  no_control_message,   // nothing received since start / since reset()
  command_timeout,      // watchdog: last control message older than `watchdog`
  telemetry_fault,      // telemetry.fault is true (any receiver fault on the Streamer)
  default_controller,   // the default (safe) controller: Streamer fallback or idle operator
  no_command_source,    // controller null and no commands in client_user_data
  drive_disabled,       // interlock not enabled
};
inline constexpr std::size_t safety_reason_count = 6;
std::string_view safety_reason_name(SafetyReason reason);  // "command_timeout", …

class SafetyReasons {
 public:
  void set(SafetyReason reason, bool active);
  bool contains(SafetyReason reason) const;
  bool empty() const { return bits_ == 0; }
  std::vector<std::string_view> names() const;  // in enum order
  bool operator==(const SafetyReasons&) const = default;

 private:
  std::uint8_t bits_ = 0;
};

struct SafetyConfig {
  Micros watchdog{300'000};           // command timeout
  double max_throttle = 1.0;          // magnitude caps
  double max_brake = 1.0;
  double max_steer = 1.0;
  double throttle_rate_per_s = 2.0;   // rate limits (units of the normalised command per s)
  double brake_rate_per_s = 5.0;
  double steer_rate_per_s = 2.0;
  double safe_brake = 1.0;            // brake level the safe state ramps to
  double neutral_deadband = 0.05;     // |stick| and trigger travel below this count as neutral
};

// Checks a config; returns a human-readable problem or nullopt when it is usable.
std::optional<std::string> validate(const SafetyConfig& config);

struct SafetyOutput {
  ActuatorCommand command;            // what the actuators get (limited, possibly safe state)
  ActuatorCommand requested;          // what the operator asked for, before limits
  DriveState drive_state = DriveState::disabled;
  SafetyReasons reasons;
  bool safe_state = true;             // == !reasons.empty()
  SimTime evaluated_at{0};
};

// Commands carried in client_user_data when the controller is null. Fields absent → nullopt.
struct UserDataCommand {
  std::optional<double> throttle;
  std::optional<double> brake;
  std::optional<double> steer;
  std::optional<bool> enable;
  bool has_motion() const { return throttle || brake || steer; }
};
// Parses {"throttle":…, "brake":…, "steer":…, "enable":…}; anything else (not an object,
// wrong types, no known field) → nullopt. Never throws.
std::optional<UserDataCommand> parse_user_data_command(std::string_view json);

// Gamepad → normalised request: right trigger = throttle, left trigger = brake, left stick x
// = steer (stick right is negative steer, i.e. right turn).
ActuatorCommand command_from_controller(const Controller& controller);
bool sticks_neutral(const Controller& controller, double deadband);

class SafetyLayer {
 public:
  explicit SafetyLayer(SafetyConfig config = {});

  // Records a fresh control message (feeds the watchdog, interlock edges and the request).
  void on_control_message(const OcpControlMessage& message, SimTime now);
  // Recomputes the output at `now`: watchdog, fault mapping, interlock, limits.
  const SafetyOutput& evaluate(SimTime now);
  // Back to the power-on state (disabled, nothing received). Used on a new connection.
  void reset(SimTime now);

  const SafetyOutput& output() const { return output_; }
  const SafetyConfig& config() const { return config_; }

 private:
  void update_interlock(bool enable_edge, bool disable_request, bool neutral);
  void apply_limits(const ActuatorCommand& target, bool safe, SimTime now);

  SafetyConfig config_;
  SafetyOutput output_;
  std::optional<SimTime> last_message_time_;
  bool telemetry_fault_ = false;
  bool default_controller_ = false;
  bool has_command_source_ = false;
  bool start_was_pressed_ = false;
  bool user_enable_was_true_ = false;
  ActuatorCommand requested_;
};

}  // namespace ocp
