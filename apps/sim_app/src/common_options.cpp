#include "sim_app/common_options.hpp"

#include <charconv>
#include <cmath>
#include <fmt/format.h>
#include <iostream>

#include "ocp/cli_checks.hpp"
#include "ocp/cli_parse.hpp"
#include "ocp/cli_paths.hpp"
#include "ocp/number_text.hpp"
#include "ocp/exit_codes.hpp"
#include "sim_app/file_loaders.hpp"

namespace ocp::sim_app {

namespace {

Error usage_error(std::string detail) {
  return Error{std::make_error_code(std::errc::invalid_argument), std::move(detail)};
}

Micros from_ms(double ms) { return Micros{static_cast<std::int64_t>(std::llround(ms * 1000.0))}; }

// Which executable each port parameter belongs to; the others act in both simulators.
struct ParamOwner {
  std::string_view param;
  std::string_view program;
  std::string_view what;
};
constexpr ParamOwner param_owners[] = {
    {"tcp_port", "streamer_sim", "the vehicle API port"},
    {"ocp_player_tcp_port", "player_sim", "the operator API port"},
};

std::string help_footer() {
  return "Plugin parameters (--plugin-param NAME VALUE, SPEC §9):\n"
         "  tcp_port              4000     0..65535 (0 = any free port)   streamer_sim: vehicle API port\n"
         "  ocp_player_tcp_port   4001     0..65535 (0 = any free port)   player_sim: operator API port\n"
         "  ocp_tcp_allow_remote  not set  presence binds 0.0.0.0 (the value is ignored)\n"
         "  latency_limit         500      1..3600000 ms: HighLatency above it\n"
         "\n"
         "--gamepad FILE: the recording format is described in docs/usage.md (\"Gamepad recordings\").\n"
         "--gamepad js:/dev/input/js0: a real joystick (xpad layout); unplugged = no gamepad.\n"
         "--ack-time-offset high = 2^62 + 12345 (a client that passes ack_time through a double breaks).\n"
         "\n"
         "Exit codes: 0 normal end (--duration-s elapsed, SIGINT/SIGTERM, --help),\n"
         "            2 bad command line, or could not start (e.g. a port in use).\n"
         "More: docs/usage.md\n";
}

}  // namespace

Result<std::uint64_t> parse_ack_time_offset(const std::string& text) {
  if (text == "high") return high_ack_time_offset;
  if (const auto value = parse_unsigned_number(text)) return *value;
  return usage_error("--ack-time-offset: expected a whole number in 0..18446744073709551615 or 'high', got " +
                     (text.empty() ? std::string("an empty value") : "'" + text + "'"));
}

std::vector<std::string> plugin_param_warnings(std::string_view program, const CommonOptions& options) {
  std::vector<std::string> warnings;
  for (const auto& group : options.plugin_param_groups) {
    if (group.empty()) continue;
    for (const ParamOwner& owner : param_owners) {
      if (group[0] != owner.param) continue;
      const bool known_program = program == "streamer_sim" || program == "player_sim";
      if (!known_program || program == owner.program) continue;
      warnings.push_back(fmt::format("--plugin-param {} has no effect in {}: it sets {} of {}", owner.param,
                                     program, owner.what, owner.program));
    }
  }
  return warnings;
}

Impairments CommonOptions::link_impairments() const {
  Impairments impairments;
  impairments.delay = from_ms(link_delay_ms);
  if (link_jitter_ms > 0.0) {
    impairments.jitter_kind = Impairments::JitterKind::uniform;
    impairments.jitter = from_ms(link_jitter_ms);
  }
  impairments.loss_probability = link_loss;
  impairments.queue_limit_packets = link_queue_packets;
  return impairments;
}

SimulatedWorldOptions CommonOptions::world_options() const {
  SimulatedWorldOptions options{plugin_params, cameras, link_impairments(), seed, gamepad, ack_time_offset};
  options.link_trace_up = link_trace_up;
  options.link_trace_down = link_trace_down;
  return options;
}

std::optional<Micros> CommonOptions::duration() const {
  if (duration_s <= 0.0) return std::nullopt;
  return Micros{static_cast<std::int64_t>(std::llround(duration_s * 1e6))};
}

void add_common_options(CLI::App& app, CommonOptions& options) {
  std::string names;
  for (const auto name : plugin_param_names()) names += (names.empty() ? "" : ", ") + std::string(name);
  app.add_option("--plugin-param", options.plugin_param_groups,
                 "OCP setting, as for the product (repeatable): " + names +
                     ". ocp_tcp_allow_remote is enabled by its presence.")
      ->type_name("NAME VALUE")
      ->expected(1, 2)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->allow_extra_args(false)
      ->group("OCP settings");

  auto* link = "Fake com channel (both directions)";
  app.add_option("--link-delay-ms", options.link_delay_ms, "one-way delay")
      ->type_name("MS")->capture_default_str()->check(cli::real(0.0, 60'000.0))->group(link);
  app.add_option("--link-jitter-ms", options.link_jitter_ms, "uniform jitter, ± this much")
      ->type_name("MS")->capture_default_str()->check(cli::real(0.0, 60'000.0))->group(link);
  app.add_option("--link-loss", options.link_loss, "random loss probability per message, 0..1")
      ->type_name("P")->capture_default_str()->check(cli::real(0.0, 1.0))->group(link);
  app.add_option("--link-trace-up", options.link_trace_up_path,
                 "Mahimahi delivery trace for the vehicle's uplink (video, feedback; docs/usage.md)")
      ->type_name("FILE")->group(link);
  app.add_option("--link-trace-down", options.link_trace_down_path,
                 "Mahimahi delivery trace for the operator's downlink (control, pings)")
      ->type_name("FILE")->group(link);
  app.add_option("--link-queue-packets", options.link_queue_packets,
                 "drop-tail queue in front of a trace, in 1500-byte packets (0 = 1000)")
      ->type_name("N")->capture_default_str()->check(cli::whole(0, 1'000'000))->group(link);

  auto* general = "General";
  app.add_option("--camera", options.camera_texts,
                 "simulated camera NAME or NAME:FPS (repeatable; default: front at 30 fps)")
      ->type_name("NAME[:FPS]")->group(general);
  app.add_option("--wire-log", options.wire_log_path,
                 "write every frame on the TCP API, both directions, as JSON lines to FILE (- = stderr); "
                 "format: docs/trace-format.md, \"frame\" events; capped at 1 GiB")
      ->check(cli::writable_file())->group(general);
  app.add_option("--gamepad", options.gamepad_text,
                 "operator gamepad: idle, drive, a recording file, or js:DEVICE (a real joystick)")
      ->capture_default_str()->group(general);
  app.add_option("--seed", options.seed, "seed for every random choice (link jitter and loss)")
      ->type_name("N")->capture_default_str()->check(cli::whole())->group(general);
  app.add_option("--ack-time-offset", options.ack_time_offset_text,
                 "added to every ack_time the Streamer issues: 0..2^64-1, or 'high' (2^62 + 12345)")
      ->type_name("N|high")->capture_default_str()->group(general);
  app.add_option("--log-level", options.log_level_text, "debug, info, warn or error")
      ->type_name("LEVEL")->capture_default_str()->group(general);
  app.add_option("--duration-s", options.duration_s,
                 "run this many seconds, then exit 0 (default: until SIGINT/SIGTERM)")
      ->type_name("S")->check(cli::real(0.0, 1e7))->group(general);
  app.footer(help_footer());
}

Result<CameraConfig> parse_camera(const std::string& text) {
  const auto colon = text.find(':');
  CameraConfig camera;
  camera.name = text.substr(0, colon);
  if (camera.name.empty()) return usage_error("--camera '" + text + "': empty camera name");
  if (colon == std::string::npos) return camera;
  const std::string fps_text = text.substr(colon + 1);
  double fps = 0.0;
  const auto [rest, error] = std::from_chars(fps_text.data(), fps_text.data() + fps_text.size(), fps);
  if (fps_text.empty() || error != std::errc{} || rest != fps_text.data() + fps_text.size() ||
      !(fps > 0.0 && fps <= 1000.0)) {
    return usage_error("--camera '" + text + "': expected NAME or NAME:FPS with FPS in (0, 1000]");
  }
  camera.fps = fps;
  return camera;
}

Status finish_common_options(CommonOptions& options) {
  PluginParams params;
  for (const auto& group : options.plugin_param_groups) {
    if (group.size() == 1 && group[0] == "ocp_tcp_allow_remote") {
      params.ocp_tcp_allow_remote = true;
      continue;
    }
    if (group.size() != 2) {
      std::string given;
      for (const auto& word : group) given += " " + word;
      return usage_error("--plugin-param expects NAME VALUE, got:" + given);
    }
    if (auto status = apply_plugin_param(params, group[0], group[1]); !status) {
      return usage_error("--plugin-param " + status.error().detail);
    }
  }
  options.plugin_params = params;

  if (!parse_log_level(options.log_level_text, options.log_level)) {
    return usage_error("--log-level '" + options.log_level_text +
                       "': expected debug, info, warn or error");
  }
  options.cameras.clear();
  for (const auto& text : options.camera_texts) {
    auto camera = parse_camera(text);
    if (!camera) return camera.error();
    for (const auto& existing : options.cameras) {
      if (existing.name == camera->name) return usage_error("--camera '" + camera->name + "' given twice");
    }
    options.cameras.push_back(std::move(*camera));
  }
  auto gamepad = parse_gamepad_script(options.gamepad_text);
  if (!gamepad) return usage_error(gamepad.error().detail);
  options.gamepad = std::move(*gamepad);
  auto offset = parse_ack_time_offset(options.ack_time_offset_text);
  if (!offset) return offset.error();
  options.ack_time_offset = *offset;
  for (auto [path, trace] : {std::pair{&options.link_trace_up_path, &options.link_trace_up},
                             std::pair{&options.link_trace_down_path, &options.link_trace_down}}) {
    if (path->empty()) continue;
    auto loaded = load_delivery_trace(*path);
    if (!loaded) return usage_error(loaded.error().detail);
    *trace = std::make_shared<const DeliveryTrace>(std::move(loaded).value());
  }
  return Ok{};
}

std::optional<int> parse_command_line(CLI::App& app, int argc, const char* const* argv,
                                      CommonOptions& options) {
  if (auto exit_code = cli::parse_or_exit_code(app, argc, argv)) return exit_code;
  if (auto status = finish_common_options(options); !status) {
    std::cerr << app.get_name() << ": " << status.error().detail
              << "\nRun with --help for the options.\n";
    return cli::exit_usage_error;
  }
  options.warnings = plugin_param_warnings(app.get_name(), options);
  for (const auto& warning : options.warnings) std::cerr << app.get_name() << ": warning: " << warning << "\n";
  return std::nullopt;
}

}  // namespace ocp::sim_app
