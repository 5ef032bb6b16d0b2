#pragma once
// Command-line option groups both simulator executables share:
//   --plugin-param NAME VALUE   (repeatable; the product's settings, SPEC §9)
//   --link-delay-ms, --link-jitter-ms, --link-loss   (the fake com channel, both directions)
//   --link-trace-up FILE, --link-trace-down FILE      (Mahimahi delivery traces, per direction)
//   --seed, --log-level, --camera NAME[:FPS] (repeatable), --duration-s
//   --gamepad idle|drive|FILE   (the simulated operator's gamepad)
//   --ack-time-offset N|high    (added to every ack_time the Streamer issues, SPEC §5)
// Every numeric value is checked strictly (ocp/cli_checks.hpp): NaN, infinities, negative or
// out-of-range and empty values are usage errors (exit code 2).
//
//   CLI::App app{"…"};
//   sim_app::CommonOptions options;
//   sim_app::add_common_options(app, options);
//   app.add_option(…);                                       // the executable's own options
//   if (auto exit_code = sim_app::parse_command_line(app, argc, argv, options)) return *exit_code;
#include <CLI/CLI.hpp>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ocp/com_channel.hpp"
#include "ocp/delivery_trace.hpp"
#include "ocp/error.hpp"
#include "ocp/log.hpp"
#include "sim_app/plugin_params.hpp"
#include "sim_app/gamepad_script.hpp"
#include "sim_app/simulated_world_options.hpp"
#include "streamer/streamer_core.hpp"

namespace ocp::sim_app {

struct CommonOptions {
  // As typed: one group per --plugin-param occurrence (NAME VALUE, or NAME alone for
  // ocp_tcp_allow_remote, whose presence is what counts).
  std::vector<std::vector<std::string>> plugin_param_groups;
  double link_delay_ms = 20.0;       // one-way
  double link_jitter_ms = 0.0;       // uniform ±
  double link_loss = 0.0;            // probability 0..1 per message
  std::string link_trace_up_path;    // "" = none; vehicle → operator (to_player)
  std::string link_trace_down_path;  // "" = none; operator → vehicle (to_streamer)
  std::size_t link_queue_packets = 0;  // the trace queue's limit; 0 = TraceQueue's default
  std::uint64_t seed = 1;
  std::string log_level_text = "info";
  std::vector<std::string> camera_texts;   // NAME or NAME:FPS
  double duration_s = 0.0;           // 0 = run until SIGINT/SIGTERM
  std::string gamepad_text = "drive";
  std::string wire_log_path;         // --wire-log: "" = none, "-" = stderr
  std::string ack_time_offset_text = "0";  // N (0..2^64-1) or "high"

  // Filled by parse_command_line from the texts above.
  PluginParams plugin_params;
  LogLevel log_level = LogLevel::info;
  std::vector<CameraConfig> cameras;       // empty when no --camera was given
  GamepadScript gamepad;
  std::uint64_t ack_time_offset = 0;
  std::shared_ptr<const DeliveryTrace> link_trace_up, link_trace_down;
  // Printed to stderr by parse_command_line too: --plugin-param names that do nothing in this
  // executable (the other simulator's port).
  std::vector<std::string> warnings;

  Impairments link_impairments() const;    // delay / jitter / loss, for both directions
  SimulatedWorldOptions world_options() const;
  std::optional<Micros> duration() const;  // nullopt = run until a signal
};

// `high`: an ack_time offset far above 2^53, where a client passing ack_time through a double
// loses the low bits. At 2^62 doubles are 1024 apart, so a rounded ack_time is wrong for 1023
// pairs in 1024 (just above 2^53 only odd values break: half the pairs, and InvalidMac would
// flap instead of staying up); below 2^63, so a signed 64-bit reader is not what breaks.
inline constexpr std::uint64_t high_ack_time_offset = (std::uint64_t{1} << 62) + 12345;
[[nodiscard]] Result<std::uint64_t> parse_ack_time_offset(const std::string& text);

// Also sets the --help footer: the plugin parameters with defaults and ranges, the exit codes,
// where the gamepad recording format is documented.
void add_common_options(CLI::App& app, CommonOptions& options);

// Warnings for --plugin-param names that have no effect in `program` ("streamer_sim",
// "player_sim"), naming the executable they belong to. Other program names: none.
std::vector<std::string> plugin_param_warnings(std::string_view program, const CommonOptions& options);

// Checks and converts what CLI11 cannot: plugin parameters, log level, cameras, ranges.
[[nodiscard]] Status finish_common_options(CommonOptions& options);

// "front" → {front, 30}; "rear:15" → {rear, 15}.
[[nodiscard]] Result<CameraConfig> parse_camera(const std::string& text);

// Parses and validates. nullopt: go on and run. Otherwise the process should exit with the
// returned code: 0 after --help, 2 after a usage error (already printed to stderr, with a
// hint to run --help).
[[nodiscard]] std::optional<int> parse_command_line(CLI::App& app, int argc, const char* const* argv,
                                                    CommonOptions& options);

}  // namespace ocp::sim_app
