#include "vehicle_app/options.hpp"

#include <CLI/CLI.hpp>
#include <cmath>
#include <iostream>

#include "ocp/cli_checks.hpp"
#include "ocp/cli_parse.hpp"

namespace ocp {
namespace {

Micros from_ms(double ms) { return Micros{static_cast<std::int64_t>(std::llround(ms * 1000.0))}; }

// The command line's option groups, one function each.
void add_safety_options(CLI::App& app, SafetyConfig& safety, double& watchdog_ms) {
  app.add_option("--watchdog-ms", watchdog_ms, "Command timeout: safe state when no control message for this long")
      ->capture_default_str()->check(cli::real(1.0, 60000.0))->group("Safety");
  app.add_option("--max-throttle", safety.max_throttle, "Throttle cap [0,1]")
      ->capture_default_str()->check(cli::real(0.0, 1.0))->group("Safety");
  app.add_option("--max-brake", safety.max_brake, "Operator brake cap [0,1]")
      ->capture_default_str()->check(cli::real(0.0, 1.0))->group("Safety");
  app.add_option("--max-steer", safety.max_steer, "Steering cap, fraction of max angle [0,1]")
      ->capture_default_str()->check(cli::real(0.0, 1.0))->group("Safety");
  app.add_option("--throttle-rate", safety.throttle_rate_per_s, "Throttle rise limit per second")
      ->capture_default_str()->check(cli::real(0.01, 1000.0))->group("Safety");
  app.add_option("--brake-rate", safety.brake_rate_per_s, "Brake change limit per second")
      ->capture_default_str()->check(cli::real(0.01, 1000.0))->group("Safety");
  app.add_option("--steer-rate", safety.steer_rate_per_s, "Steering change limit per second")
      ->capture_default_str()->check(cli::real(0.01, 1000.0))->group("Safety");
  app.add_option("--safe-brake", safety.safe_brake, "Brake level of the safe state (0,1]")
      ->capture_default_str()->check(cli::real(0.0, 1.0))->group("Safety");
}

void add_vehicle_options(CLI::App& app, VehicleClientConfig& client) {
  VehicleParams& vehicle = client.vehicle;
  app.add_option("--start-lat", client.start.lat, "Start latitude, degrees")
      ->capture_default_str()->check(cli::real(-89.0, 89.0))->group("Vehicle");
  app.add_option("--start-lon", client.start.lon, "Start longitude, degrees")
      ->capture_default_str()->check(cli::real(-180.0, 180.0))->group("Vehicle");
  app.add_option("--start-heading-deg", client.start_heading_deg, "Start compass heading (0 = north)")
      ->capture_default_str()->check(cli::real(-360.0, 360.0))->group("Vehicle");
  app.add_option("--wheelbase-m", vehicle.wheelbase_m, "Wheelbase")
      ->capture_default_str()->check(cli::real(0.1, 50.0))->group("Vehicle");
  app.add_option("--max-steer-rad", vehicle.max_steer_rad, "Road-wheel angle at full steering")
      ->capture_default_str()->check(cli::real(0.01, 1.5))->group("Vehicle");
  app.add_option("--max-speed-mps", vehicle.max_speed_mps, "Top speed")
      ->capture_default_str()->check(cli::real(0.1, 100.0))->group("Vehicle");
}

void add_misbehaviour_options(CLI::App& app, Misbehaviour& misbehave, double& delay_ms, std::string& bad_response) {
  const std::string misbehave_group = "Misbehaviour (tests and demos only; all off by default)";
  app.add_flag("--misbehave-stop-echo", misbehave.stop_echo,
               "Keep echoing the first ack pair (Streamer: HighLatency)")->group(misbehave_group);
  app.add_flag("--misbehave-corrupt-mac", misbehave.corrupt_mac,
               "Echo a wrong ack_time_mac (Streamer: InvalidMac)")->group(misbehave_group);
  app.add_option("--misbehave-delay-responses-ms", delay_ms,
                 "Send every response this late (latency grows)")
      ->check(cli::real(0.0, 60000.0))->group(misbehave_group);
  app.add_flag("--misbehave-oversized-frames", misbehave.oversized_frames,
               "Send >16 KiB responses (drained; InvalidMac)")->group(misbehave_group);
  app.add_flag("--misbehave-ack-through-double", misbehave.ack_through_double,
               "Round ack_time through a double (breaks > 2^53)")->group(misbehave_group);
  app.add_flag("--misbehave-malformed-json", misbehave.malformed_json,
               "Send truncated JSON (Streamer closes the connection)")->group(misbehave_group);
  app.add_flag("--misbehave-silent", misbehave.silent,
               "Never send a response (Streamer's 2 s read timeout)")->group(misbehave_group);
  std::vector<std::string> kinds;
  for (BadResponse kind : {BadResponse::missing_field, BadResponse::wrong_type, BadResponse::not_an_object,
                           BadResponse::ack_time_out_of_range, BadResponse::eof_mid_frame}) {
    kinds.emplace_back(bad_response_name(kind));
  }
  app.add_option("--misbehave-bad-response", bad_response,
                 "Break every response one way (Streamer closes the connection; SPEC §2)")
      ->check(CLI::IsMember(kinds))->group(misbehave_group);
}

}  // namespace

ParseOutcome parse_program_options(int argc, const char* const* argv) {
  ProgramOptions options;
  VehicleClientConfig& client = options.client;
  SafetyConfig& safety = client.safety;
  Misbehaviour& misbehave = client.misbehave;

  CLI::App app{
      "Reference OCP vehicle client: connects to a Streamer's vehicle-side TCP API, echoes the\n"
      "latency-loop pair immediately after every control message, runs a safety layer and a\n"
      "kinematic bicycle model, and reports position and state as vehicle_user_data.",
      "vehicle_client"};
  app.get_formatter()->column_width(40);
  app.footer(
      "Exit codes: 0 normal end (--duration-s elapsed, SIGINT/SIGTERM, --help),\n"
      "            1 the connection ended or failed with --no-reconnect, 2 bad command line.\n"
      "More: docs/vehicle_client.md\n");

  std::string server = "127.0.0.1:4000";
  app.add_option("server", server, "Streamer vehicle API as host:port")->capture_default_str();

  double watchdog_ms = 300.0;
  add_safety_options(app, safety, watchdog_ms);
  add_vehicle_options(app, client);

  double connect_timeout_ms = 2000.0;
  bool no_reconnect = false;
  std::string log_level = "info";
  double response_period_ms = 10.0;
  app.add_option("--response-period-ms", response_period_ms, "Longest gap between two responses")
      ->capture_default_str()->check(cli::real(1.0, 1000.0))->group("Connection");
  app.add_option("--connect-timeout-ms", connect_timeout_ms, "Give up one connect attempt after this long")
      ->capture_default_str()->check(cli::real(1.0, 600000.0))->group("Connection");
  app.add_flag("--no-reconnect", no_reconnect, "Exit (code 1) when the connection fails or ends")
      ->group("Connection");
  app.add_option("--log-level", log_level, "debug | info | warn | error")
      ->capture_default_str()->check(CLI::IsMember({"debug", "info", "warn", "warning", "error"}));
  app.add_option("--duration-s", options.duration_s, "Run this many seconds, then exit 0")
      ->check(cli::real(0.001, 1e7));
  bool no_status = false;
  app.add_flag("--no-status", no_status, "Do not print the once-per-second status line");

  double delay_ms = 0.0;
  std::string bad_response = "none";
  add_misbehaviour_options(app, misbehave, delay_ms, bad_response);

  if (auto exit_code = cli::parse_or_exit_code(app, argc, argv)) return {std::nullopt, *exit_code};

  const auto fail = [](const std::string& message) {
    std::cerr << "vehicle_client: " << message << "\nRun with --help for more information.\n";
    return ParseOutcome{std::nullopt, 2};
  };
  Result<Endpoint> endpoint = parse_endpoint(server);
  if (!endpoint.ok()) return fail(endpoint.error().detail);
  const bool port_given = server.starts_with('[') ? server.find("]:") != std::string::npos : server.find(':') != std::string::npos;
  if (!port_given) {
    std::cerr << "vehicle_client: no port in \"" << server << "\": using " << endpoint->port
              << " (the Streamer's default tcp_port); give host:port to choose\n";
  }
  options.runner.server = *endpoint;
  options.runner.connect_timeout = from_ms(connect_timeout_ms);
  options.runner.reconnect = !no_reconnect;
  safety.watchdog = from_ms(watchdog_ms);
  client.response_period = from_ms(response_period_ms);
  misbehave.delay_responses = from_ms(delay_ms);
  misbehave.bad_response = parse_bad_response(bad_response).value_or(BadResponse::none);
  options.status_line = !no_status;
  if (!parse_log_level(log_level, options.log_level)) return fail("unknown log level " + log_level);
  if (auto problem = validate(client)) return fail(*problem);
  return {std::move(options), 0};
}

}  // namespace ocp
