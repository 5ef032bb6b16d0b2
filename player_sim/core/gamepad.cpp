// Scriptable gamepad: idle, constant, waveform and recorded playback (see gamepad.hpp).
#include "player/gamepad.hpp"
#include "ocp/escaped_excerpt.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <numbers>
#include <sstream>

namespace ocp {
namespace {

constexpr std::array<GamepadAxis, 6> all_axes = {
    GamepadAxis::left_x,  GamepadAxis::left_y,       GamepadAxis::right_x,
    GamepadAxis::right_y, GamepadAxis::left_trigger, GamepadAxis::right_trigger};

struct ButtonField {
  std::string_view name;
  bool Buttons::*member;
};
constexpr std::array<ButtonField, 15> button_fields = {{
    {"a", &Buttons::a},
    {"b", &Buttons::b},
    {"x", &Buttons::x},
    {"y", &Buttons::y},
    {"left_bumper", &Buttons::left_bumper},
    {"right_bumper", &Buttons::right_bumper},
    {"back", &Buttons::back},
    {"start", &Buttons::start},
    {"guide", &Buttons::guide},
    {"left_thumb", &Buttons::left_thumb},
    {"right_thumb", &Buttons::right_thumb},
    {"dpad_up", &Buttons::dpad_up},
    {"dpad_right", &Buttons::dpad_right},
    {"dpad_down", &Buttons::dpad_down},
    {"dpad_left", &Buttons::dpad_left},
}};

Error recording_error(std::size_t line_number, const std::string& what) {
  return Error{std::make_error_code(std::errc::invalid_argument),
               "recording line " + std::to_string(line_number) + ": " + what};
}

// Applies one "name=value" field to `controller`; returns an error text or "".
std::string apply_field(std::string_view field, Controller& controller) {
  const auto equals = field.find('=');
  if (equals == std::string_view::npos) return "expected name=value, got '" + escaped_excerpt(field) + "'";
  const std::string_view name = field.substr(0, equals);
  const std::string value_text(field.substr(equals + 1));
  for (GamepadAxis axis : all_axes) {
    if (gamepad_axis_name(axis) != name) continue;
    // strtod keeps this independent of from_chars floating-point support.
    char* end = nullptr;
    const double value = std::strtod(value_text.c_str(), &end);
    if (value_text.empty() || end != value_text.c_str() + value_text.size() || !std::isfinite(value) ||
        value < -1.0 || value > 1.0) {
      return "axis '" + escaped_excerpt(name) + "' needs a number in [-1, 1], got '" + escaped_excerpt(value_text) + "'";
    }
    axis_value(controller.axes, axis) = value;
    return "";
  }
  for (const ButtonField& button : button_fields) {
    if (button.name != name) continue;
    if (value_text != "0" && value_text != "1") {
      return "button '" + escaped_excerpt(name) + "' needs 0 or 1, got '" + escaped_excerpt(value_text) + "'";
    }
    controller.buttons.*button.member = value_text == "1";
    return "";
  }
  return "unknown field '" + escaped_excerpt(name) + "'";
}

}  // namespace

std::string_view gamepad_axis_name(GamepadAxis axis) {
  switch (axis) {
    case GamepadAxis::left_x: return "left_x";
    case GamepadAxis::left_y: return "left_y";
    case GamepadAxis::right_x: return "right_x";
    case GamepadAxis::right_y: return "right_y";
    case GamepadAxis::left_trigger: return "left_trigger";
    case GamepadAxis::right_trigger: return "right_trigger";
  }
  return "?";
}

std::optional<double> controller_field(const Controller& controller, std::string_view name) {
  Axes axes = controller.axes;   // axis_value hands out a reference: read a copy
  for (GamepadAxis axis : all_axes) {
    if (gamepad_axis_name(axis) == name) return axis_value(axes, axis);
  }
  for (const ButtonField& button : button_fields) {
    if (button.name == name) return controller.buttons.*button.member ? 1.0 : 0.0;
  }
  return std::nullopt;
}

double& axis_value(Axes& axes, GamepadAxis axis) {
  switch (axis) {
    case GamepadAxis::left_x: return axes.left_x;
    case GamepadAxis::left_y: return axes.left_y;
    case GamepadAxis::right_x: return axes.right_x;
    case GamepadAxis::right_y: return axes.right_y;
    case GamepadAxis::left_trigger: return axes.left_trigger;
    case GamepadAxis::right_trigger: return axes.right_trigger;
  }
  return axes.left_x;
}

Result<Recording> parse_recording(std::string_view text) {
  Recording recording;
  std::size_t line_number = 0;
  std::size_t position = 0;
  while (position <= text.size()) {
    const std::size_t line_end = std::min(text.find('\n', position), text.size());
    std::string line(text.substr(position, line_end - position));
    position = line_end + 1;
    ++line_number;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream words(line);
    std::string time_text;
    if (!(words >> time_text)) continue;  // blank or comment-only line
    std::uint64_t time_ms = 0;
    const auto [end, error] =
        std::from_chars(time_text.data(), time_text.data() + time_text.size(), time_ms);
    if (error != std::errc{} || end != time_text.data() + time_text.size() ||
        time_ms > 1'000'000'000'000ULL) {
      return recording_error(line_number, "expected a time in ms, got '" + escaped_excerpt(time_text) + "'");
    }
    RecordedState state;
    state.time = Micros{static_cast<std::int64_t>(time_ms) * 1000};
    if (!recording.states.empty() && state.time < recording.states.back().time) {
      return recording_error(line_number, "time goes backwards");
    }
    std::string field;
    while (words >> field) {
      if (std::string problem = apply_field(field, state.controller); !problem.empty()) {
        return recording_error(line_number, problem);
      }
    }
    recording.states.push_back(state);
  }
  return recording;
}

std::string format_recording(const Recording& recording) {
  std::string out;
  const Controller neutral;
  for (const RecordedState& state : recording.states) {
    out += std::to_string(state.time.count() / 1000);
    for (GamepadAxis axis : all_axes) {
      Axes axes = state.controller.axes;
      Axes neutral_axes = neutral.axes;
      const double value = axis_value(axes, axis);
      if (value == axis_value(neutral_axes, axis)) continue;
      std::ostringstream number;
      number.precision(17);
      number << value;
      out += ' ';
      out += gamepad_axis_name(axis);
      out += '=';
      out += number.str();
    }
    for (const ButtonField& button : button_fields) {
      if (!(state.controller.buttons.*button.member)) continue;
      out += ' ';
      out += button.name;
      out += "=1";
    }
    out += '\n';
  }
  return out;
}

void Gamepad::set_idle() { mode_ = Mode::idle; }

void Gamepad::set_constant(const Controller& controller) {
  mode_ = Mode::constant;
  constant_ = controller;
}

void Gamepad::set_waveform(Waveform waveform, SimTime start) {
  mode_ = Mode::waveform;
  waveform_ = std::move(waveform);
  start_ = start;
}

void Gamepad::set_recording(Recording recording, SimTime start, bool loop) {
  mode_ = Mode::recording;
  recording_ = std::move(recording);
  start_ = start;
  loop_ = loop;
}

void Gamepad::set_source(Source source) {
  mode_ = Mode::external;
  source_ = std::move(source);
}

std::optional<Controller> Gamepad::sample(SimTime now) const {
  if (!plugged_) return std::nullopt;
  switch (mode_) {
    case Mode::idle: return Controller::safe_default();
    case Mode::constant: return constant_;
    case Mode::waveform: return sample_waveform(now);
    case Mode::recording: return sample_recording(now);
    case Mode::external: return source_ ? source_(now) : std::nullopt;
  }
  return Controller::safe_default();
}

Controller Gamepad::sample_waveform(SimTime now) const {
  Controller controller = waveform_.base;
  const double elapsed_seconds = static_cast<double>((now - start_).count()) / 1e6;
  for (const SineWave& wave : waveform_.waves) {
    if (wave.period.count() <= 0) continue;
    const double period_seconds = static_cast<double>(wave.period.count()) / 1e6;
    const double angle = 2.0 * std::numbers::pi * elapsed_seconds / period_seconds + wave.phase_radians;
    axis_value(controller.axes, wave.axis) += wave.amplitude * std::sin(angle);
  }
  for (GamepadAxis axis : all_axes) {
    double& value = axis_value(controller.axes, axis);
    value = std::clamp(value, -1.0, 1.0);
  }
  return controller;
}

Controller Gamepad::sample_recording(SimTime now) const {
  const std::vector<RecordedState>& states = recording_.states;
  if (states.empty()) return Controller::safe_default();
  Micros playback = now - start_;
  if (playback < Micros{0}) return Controller::safe_default();
  const Micros loop_length = states.back().time;
  if (loop_ && loop_length > Micros{0}) playback = playback % loop_length;
  // The last state whose time is <= playback holds until the next one.
  const auto after = std::upper_bound(
      states.begin(), states.end(), playback,
      [](Micros time, const RecordedState& state) { return time < state.time; });
  if (after == states.begin()) return Controller::safe_default();
  return std::prev(after)->controller;
}

}  // namespace ocp
