// vehicle_client — the reference OCP vehicle integration. Copy this program to start your own:
// replace the Eigen bicycle model (vehicle_model.hpp) with your vehicle bridge and adapt the
// safety layer; keep the response path exactly as it is. See docs/vehicle_client.md.
#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <csignal>
#include <string>

#include "ocp/asio/executor.hpp"
#include "sim_app/latency_window.hpp"
#include "ocp/log.hpp"
#include "vehicle_app/options.hpp"
#include "vehicle_app/tcp_runner.hpp"
#include "vehicle_client/vehicle_client.hpp"

namespace {

// `latency`: the telemetry latencies of the second (see the sampler in main).
std::string status_line(const ocp::VehicleClient& client, const ocp::LatencyWindow& latency) {
  const ocp::VehicleClientStats& stats = client.stats();
  const ocp::SafetyOutput& safety = client.safety();
  const ocp::VehicleState& vehicle = client.vehicle();
  std::string reasons;
  for (std::string_view name : safety.reasons.names()) {
    if (!reasons.empty()) reasons += ',';
    reasons += name;
  }
  return fmt::format(
      "status: {} | latency {} | fault: {} | drive: {} | safe: {} | {:.2f} m/s heading {:.1f} | rx {} tx {}",
      client.connected() ? "connected" : "NOT connected",
      client.connected() ? latency.format() : std::string("n/a (no loop running)"),
      stats.last_telemetry_fault ? stats.last_fault_reason : "none", ocp::drive_state_name(safety.drive_state),
      safety.safe_state ? reasons : "no", vehicle.speed_mps, vehicle.heading_deg(),
      stats.control_messages_received, stats.responses_sent);
}

}  // namespace

int main(int argc, char** argv) {
  ocp::ParseOutcome parsed = ocp::parse_program_options(argc, argv);
  if (!parsed.options) return parsed.exit_code;
  const ocp::ProgramOptions& options = *parsed.options;

  boost::asio::io_context io;
  ocp::AsioExecutor executor(io);
  const ocp::LogSink sink = ocp::make_console_sink(options.log_level);
  const ocp::Logger logger(executor, "vehicle-client", sink);
  ocp::VehicleClient client(executor, options.client, logger);
  ocp::TcpRunner runner(executor, client, options.runner, logger.child("tcp"));
  boost::asio::signal_set signals(io, SIGINT, SIGTERM, SIGHUP);   // SIGHUP: a closed SSH session
  std::signal(SIGPIPE, SIG_IGN);   // a closed stdout is no reason to stop driving

  int exit_code = 0;
  bool stopping = false;
  // Every control message's telemetry latency goes into the second's min/avg/max; sampled on
  // the control period so the core needs no status hook.
  ocp::LatencyWindow latency;
  std::uint64_t sampled_messages = 0;
  ocp::PeriodicTimer latency_sampler(executor, ocp::Micros{10'000}, [&](ocp::SimTime) {
    const auto& stats = client.stats();
    if (stats.control_messages_received == sampled_messages) return;
    sampled_messages = stats.control_messages_received;
    latency.add(stats.last_latency_ms);
  });
  ocp::PeriodicTimer status_timer(executor, ocp::Micros{1'000'000}, [&](ocp::SimTime) {
    logger.info("{}", status_line(client, latency));
    latency.reset();
  });
  const auto shutdown = [&](int code, const std::string& why) {
    if (stopping) return;
    stopping = true;
    exit_code = code;
    logger.info("shutting down: {}", why);
    status_timer.stop();
    latency_sampler.stop();
    runner.stop();
    signals.cancel();
    io.stop();  // the model timer and stream handlers would keep the loop alive
  };

  signals.async_wait([&](const boost::system::error_code& error, int signal_number) {
    if (!error) shutdown(0, signal_number == SIGINT ? "SIGINT" : signal_number == SIGHUP ? "SIGHUP" : "SIGTERM");
  });
  if (options.duration_s) {
    executor.call_after(ocp::Micros{static_cast<std::int64_t>(*options.duration_s * 1e6)},
                        [&] { shutdown(0, "--duration-s elapsed"); });
  }
  runner.set_on_event([&](const ocp::RunnerConnectionEvent& event) {
    if (event.kind == ocp::ConnectionEventKind::stopped && !options.runner.reconnect) {
      shutdown(1, "connection ended and --no-reconnect is set");
    }
  });
  if (options.status_line) {
    status_timer.start(executor.now() + ocp::Micros{1'000'000});
    latency_sampler.start(executor.now() + ocp::Micros{10'000});
  }

  logger.info("vehicle client for {} (watchdog {} ms, start {:.6f},{:.6f})", options.runner.server.to_string(),
              ocp::to_whole_ms(options.client.safety.watchdog), options.client.start.lat, options.client.start.lon);
  runner.start();
  io.run();
  return exit_code;
}
