#pragma once
// A scriptable gamepad (SPEC §4.4). The Player samples it once per frame; nothing here reads
// a clock or a device, so the same script gives the same samples in virtual and real time.
//
// Modes:
//   idle      — connected, neutral (the safe default controller).
//   constant  — always the given controller.
//   waveform  — a base controller plus sine waves on chosen axes (period, amplitude, phase),
//               evaluated at (now − start); deterministic, clamped to [-1, 1].
//   recording — timestamped controller states played back step-wise (each state holds until
//               the next one), optionally looped. Text format below.
//   external  — a live device behind a function (e.g. LinuxJoystick, linux_joystick.hpp);
//               the function returning nullopt means the device is absent (unplugged).
// unplug()/replug() are independent of the mode: while unplugged sample() returns nullopt.
//
// Recording text format (one record a line; '#' starts a comment; blank lines ignored):
//   <time_ms> [name=value ...]
// time_ms is a non-negative integer, non-decreasing from line to line, relative to the start
// of playback. Names are the axis names (left_x left_y right_x right_y left_trigger
// right_trigger; value a number in [-1, 1]) and the button names (a b x y left_bumper
// right_bumper back start guide left_thumb right_thumb dpad_up dpad_right dpad_down
// dpad_left; value 0 or 1). Fields not named take their safe default value, so each line is a
// complete state. Before the first record the safe default is reported. Looping: the loop
// length is the time of the last line; a last line with no fields ("2000") just marks it.
//   0    left_y=0.5 a=1
//   500  left_y=0.5 right_trigger=0.2
//   1000
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ocp/error.hpp"
#include "ocp/messages.hpp"
#include "ocp/time.hpp"

namespace ocp {

enum class GamepadAxis { left_x, left_y, right_x, right_y, left_trigger, right_trigger };
std::string_view gamepad_axis_name(GamepadAxis axis);
// Reference to one axis of a controller (for scripting and parsing).
double& axis_value(Axes& axes, GamepadAxis axis);
// One field of a controller by its recording-format name (below): an axis's value, a button as
// 1 or 0; nullopt for a name that is neither (scenario expectations on axis and button values).
std::optional<double> controller_field(const Controller& controller, std::string_view name);

struct SineWave {
  GamepadAxis axis = GamepadAxis::left_x;
  double amplitude = 1.0;          // added to the base value, result clamped to [-1, 1]
  Micros period{1'000'000};
  double phase_radians = 0.0;
};

struct Waveform {
  Controller base;                 // buttons and the axes not driven by a wave
  std::vector<SineWave> waves;     // several waves on one axis add up
};

struct RecordedState {
  Micros time{0};                  // from the start of playback
  Controller controller;
};

struct Recording {
  std::vector<RecordedState> states;   // time non-decreasing
};

// Parses the text format above; errors name the line ("line 3: unknown field 'foo'").
Result<Recording> parse_recording(std::string_view text);
// (Reading a recording file is the app layer's job: sim_app::load_gamepad_recording.)
// Writes the text format (round-trips through parse_recording for values it can print).
std::string format_recording(const Recording& recording);

class Gamepad {
 public:
  enum class Mode { idle, constant, waveform, recording, external };
  // A live source: the state at `now`, or nullopt while the device is absent.
  using Source = std::function<std::optional<Controller>(SimTime now)>;

  Gamepad() = default;

  void set_idle();
  void set_constant(const Controller& controller);
  // Waves are evaluated at (now − start).
  void set_waveform(Waveform waveform, SimTime start = SimTime{0});
  // Playback time is (now − start); looping repeats with the recording's last time as period.
  // An empty recording behaves as idle.
  void set_recording(Recording recording, SimTime start = SimTime{0}, bool loop = false);

  // A live device; sample() asks it every frame (real time only: devices are not virtual).
  void set_source(Source source);

  void unplug() { plugged_ = false; }
  void replug() { plugged_ = true; }
  bool plugged() const { return plugged_; }
  Mode mode() const { return mode_; }

  // The state at `now`; nullopt while unplugged. Pure function of (script, now).
  std::optional<Controller> sample(SimTime now) const;

 private:
  Controller sample_waveform(SimTime now) const;
  Controller sample_recording(SimTime now) const;

  Mode mode_ = Mode::idle;
  bool plugged_ = true;
  Controller constant_;
  Waveform waveform_;
  Recording recording_;
  SimTime start_{0};
  bool loop_ = false;
  Source source_;
};

}  // namespace ocp
