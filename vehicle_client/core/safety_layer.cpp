#include "vehicle_client/safety_layer.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "ocp/invariant.hpp"

namespace ocp {
namespace {

constexpr std::array<std::string_view, safety_reason_count> reason_names = {
    "no_control_message", "command_timeout",   "telemetry_fault",
    "default_controller", "no_command_source", "drive_disabled",
};

double clamp_unit(double value, double low, double high) {
  // JSON numbers are always finite, but a hand-built message could carry NaN: treat as 0.
  if (!std::isfinite(value)) return 0.0;
  return std::clamp(value, low, high);
}

// Moves `current` toward `target` by at most `max_change`.
double step_toward(double current, double target, double max_change) {
  if (target > current) return std::min(target, current + max_change);
  return std::max(target, current - max_change);
}

// Trigger raw value [-1 (released), 1 (pressed)] → travel [0, 1].
double trigger_travel(double raw) { return (clamp_unit(raw, -1.0, 1.0) + 1.0) / 2.0; }

}  // namespace

std::string_view drive_state_name(DriveState state) {
  return state == DriveState::enabled ? "enabled" : "disabled";
}

std::string_view safety_reason_name(SafetyReason reason) {
  return reason_names[static_cast<std::size_t>(reason)];
}

void SafetyReasons::set(SafetyReason reason, bool active) {
  const auto bit = static_cast<std::uint8_t>(1u << static_cast<unsigned>(reason));
  bits_ = active ? static_cast<std::uint8_t>(bits_ | bit) : static_cast<std::uint8_t>(bits_ & ~bit);
}

bool SafetyReasons::contains(SafetyReason reason) const {
  return (bits_ >> static_cast<unsigned>(reason)) & 1u;
}

std::vector<std::string_view> SafetyReasons::names() const {
  std::vector<std::string_view> result;
  for (std::size_t index = 0; index < safety_reason_count; ++index) {
    if (contains(static_cast<SafetyReason>(index))) result.push_back(reason_names[index]);
  }
  return result;
}

std::optional<std::string> validate(const SafetyConfig& config) {
  if (config.watchdog.count() <= 0) return "watchdog must be positive";
  const auto in_unit = [](double value) { return std::isfinite(value) && value >= 0.0 && value <= 1.0; };
  if (!in_unit(config.max_throttle)) return "max throttle must be in [0, 1]";
  if (!in_unit(config.max_brake)) return "max brake must be in [0, 1]";
  if (!in_unit(config.max_steer)) return "max steer must be in [0, 1]";
  if (!in_unit(config.safe_brake) || config.safe_brake == 0.0) return "safe brake must be in (0, 1]";
  if (!in_unit(config.neutral_deadband)) return "neutral deadband must be in [0, 1]";
  for (double rate : {config.throttle_rate_per_s, config.brake_rate_per_s, config.steer_rate_per_s}) {
    if (!std::isfinite(rate) || rate <= 0.0) return "rate limits must be positive (per second)";
  }
  return std::nullopt;
}

ActuatorCommand command_from_controller(const Controller& controller) {
  return ActuatorCommand{
      .throttle = trigger_travel(controller.axes.right_trigger),
      .brake = trigger_travel(controller.axes.left_trigger),
      // Stick right (+x) steers right, which is negative (clockwise) in the model.
      .steer = -clamp_unit(controller.axes.left_x, -1.0, 1.0),
  };
}

bool sticks_neutral(const Controller& controller, double deadband) {
  const Axes& axes = controller.axes;
  const auto centred = [deadband](double value) { return std::abs(value) < deadband; };
  return centred(axes.left_x) && centred(axes.left_y) && centred(axes.right_x) &&
         centred(axes.right_y) && trigger_travel(axes.left_trigger) < deadband &&
         trigger_travel(axes.right_trigger) < deadband;
}

SafetyLayer::SafetyLayer(SafetyConfig config) : config_(config) {
  // Power-on: parked with the safe brake applied, nothing received yet.
  output_.command = ActuatorCommand{0.0, config_.safe_brake, 0.0};
  output_.reasons.set(SafetyReason::no_control_message, true);
  output_.reasons.set(SafetyReason::drive_disabled, true);
}

void SafetyLayer::reset(SimTime now) {
  // The actuators are physical: keep their current positions, forget everything else.
  const ActuatorCommand current = output_.command;
  *this = SafetyLayer(config_);
  output_.command = current;
  output_.evaluated_at = now;
}

void SafetyLayer::on_control_message(const OcpControlMessage& message, SimTime now) {
  last_message_time_ = now;
  telemetry_fault_ = message.telemetry.fault;

  bool enable_edge = false;
  bool disable_request = false;
  bool neutral = true;
  if (message.controller) {
    const Controller& controller = *message.controller;
    default_controller_ = controller.is_safe_default();
    has_command_source_ = true;
    requested_ = command_from_controller(controller);
    enable_edge = controller.buttons.start && !start_was_pressed_;
    start_was_pressed_ = controller.buttons.start;
    disable_request = controller.buttons.back;
    neutral = sticks_neutral(controller, config_.neutral_deadband);
    user_enable_was_true_ = false;
  } else {
    default_controller_ = false;
    start_was_pressed_ = false;
    std::optional<UserDataCommand> command;
    if (message.client_user_data) command = parse_user_data_command(message.client_user_data->text);
    has_command_source_ = command && command->has_motion();
    requested_ = has_command_source_
                     ? ActuatorCommand{clamp_unit(command->throttle.value_or(0.0), 0.0, 1.0),
                                       clamp_unit(command->brake.value_or(0.0), 0.0, 1.0),
                                       clamp_unit(command->steer.value_or(0.0), -1.0, 1.0)}
                     : ActuatorCommand{};
    const bool enable_true = command && command->enable == true;
    enable_edge = enable_true && !user_enable_was_true_;
    user_enable_was_true_ = enable_true;
    disable_request = command && command->enable == false;
    neutral = requested_.throttle < config_.neutral_deadband &&
              requested_.brake < config_.neutral_deadband &&
              std::abs(requested_.steer) < config_.neutral_deadband;
  }
  update_interlock(enable_edge, disable_request, neutral);
}

void SafetyLayer::update_interlock(bool enable_edge, bool disable_request, bool neutral) {
  if (disable_request) {
    output_.drive_state = DriveState::disabled;
    return;
  }
  // Enabling is a deliberate act: a fresh press, sticks at rest, a command source, no fault.
  if (enable_edge && neutral && has_command_source_ && !telemetry_fault_) {
    output_.drive_state = DriveState::enabled;
  }
}

const SafetyOutput& SafetyLayer::evaluate(SimTime now) {
  SafetyReasons& reasons = output_.reasons;
  const bool never_received = !last_message_time_.has_value();
  const bool timed_out = !never_received && now - *last_message_time_ >= config_.watchdog;
  reasons.set(SafetyReason::no_control_message, never_received);
  reasons.set(SafetyReason::command_timeout, timed_out);
  reasons.set(SafetyReason::telemetry_fault, !never_received && telemetry_fault_);
  reasons.set(SafetyReason::default_controller, !never_received && default_controller_);
  reasons.set(SafetyReason::no_command_source, !never_received && !has_command_source_);

  // Faults latch the interlock off: after a fault the operator must enable again.
  if (never_received || timed_out || telemetry_fault_) output_.drive_state = DriveState::disabled;
  reasons.set(SafetyReason::drive_disabled, output_.drive_state != DriveState::enabled);

  output_.safe_state = !reasons.empty();
  output_.requested = requested_;
  const ActuatorCommand target =
      output_.safe_state ? ActuatorCommand{0.0, config_.safe_brake, output_.command.steer} : requested_;
  apply_limits(target, output_.safe_state, now);
  output_.evaluated_at = now;
  OCP_INVARIANT(output_.safe_state == !reasons.empty(), "the safe state holds exactly while a safety reason does");
  OCP_INVARIANT(!output_.safe_state || output_.command.throttle == 0.0, "no throttle in the safe state");
  OCP_INVARIANT(!(never_received || timed_out || telemetry_fault_) || output_.drive_state == DriveState::disabled,
                "a missing, late or faulted control stream disables driving");
  return output_;
}

void SafetyLayer::apply_limits(const ActuatorCommand& target, bool safe, SimTime now) {
  const double dt_s = now > output_.evaluated_at
                          ? std::chrono::duration<double>(now - output_.evaluated_at).count()
                          : 0.0;
  ActuatorCommand& command = output_.command;

  // Magnitude. In the safe state the brake goes to safe_brake regardless of the operator cap.
  double throttle = clamp_unit(target.throttle, 0.0, config_.max_throttle);
  const double brake =
      safe ? target.brake : clamp_unit(target.brake, 0.0, config_.max_brake);
  const double steer = clamp_unit(target.steer, -config_.max_steer, config_.max_steer);
  // Brake wins over throttle when the operator asks for both.
  if (brake >= config_.neutral_deadband) throttle = 0.0;

  // Rate. Throttle may drop at once (removing drive is always safe) but rises at its rate;
  // brake and steering move at their rates both ways, so nothing jerks.
  command.throttle = throttle <= command.throttle
                         ? throttle
                         : step_toward(command.throttle, throttle, config_.throttle_rate_per_s * dt_s);
  command.brake = step_toward(command.brake, brake, config_.brake_rate_per_s * dt_s);
  command.steer = step_toward(command.steer, steer, config_.steer_rate_per_s * dt_s);
  OCP_INVARIANT(command.throttle >= 0.0 && command.throttle <= std::max(config_.max_throttle, 0.0) + 1e-12,
                "throttle stays within [0, max_throttle]");
}

}  // namespace ocp
