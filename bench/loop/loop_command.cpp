#include "loop_command.hpp"

#include <sys/prctl.h>
#include <unistd.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <chrono>
#include <csignal>
#include <fstream>
#include <iostream>
#include <memory>

#include "bare_client.hpp"
#include "child_process.hpp"
#include "floor_echo.hpp"
#include "loop_gates.hpp"
#include "loop_recorder.hpp"
#include "loop_report.hpp"
#include "loop_result.hpp"
#include "ocp/asio_executor.hpp"
#include "streamer_app/streamer_simulation.hpp"
#include "timer_client.hpp"
#include "ocp/cli_checks.hpp"

namespace ocp::bench {

CLI::App* add_loop_command(CLI::App& app, LoopOptions& options) {
  CLI::App* loop = app.add_subcommand(
      "loop",
      "Measure a vehicle client against a Streamer with a simulated operator on 127.0.0.1:\n"
      "echo delay, responses, OCP latency, tick lateness and faults, from the Streamer's events.\n"
      "  ocp_bench loop --port 4000                       wait for your client on :4000\n"
      "  ocp_bench loop -- ./my_client 127.0.0.1:{port}  launch it ({port} and $OCP_PORT)");
  loop->add_option("--port", options.port, "Streamer TCP port (default: 4000 when waiting, a free one with a command)");
  loop->add_option("--duration-s", options.duration_s, "measurement time from the client's connection")
      ->capture_default_str()->check(ocp::cli::real(0.1, 86400.0));
  loop->add_option("--connect-timeout-s", options.connect_timeout_s, "give up when no client connects within this")
      ->capture_default_str()->check(ocp::cli::real(0.1, 3600.0));
  loop->add_option("--json", options.json_path, "write the figures as JSON to FILE");
  loop->add_option("--html", options.html_path, "write a self-contained HTML page (inline SVG) to FILE");
  loop->add_flag("--compare", options.compare,
                 "also measure, in the same run: the machine floor (bare blocking-socket echo, no Streamer),\n"
                 "a bare client (blocking read, libocp codec, answers at once) against a Streamer of its own,\n"
                 "and a client answering on its own 10 ms timer; print the client's ratios to each");
  loop->add_flag("--quiet", options.quiet, "no progress line");
  loop->add_option("--max-echo-p50-us", options.max_echo_p50_us, "gate: fail (exit 1) when the client's echo delay p50 is above this")
      ->check(ocp::cli::positive_real(1e9));
  loop->add_option("--max-echo-p99-us", options.max_echo_p99_us, "gate: fail (exit 1) when the client's echo delay p99 is above this")
      ->check(ocp::cli::positive_real(1e9));
  loop->add_option("--max-floor-ratio", options.max_floor_ratio,
                   "gate: fail (exit 1) when the client's echo p50 is more than this many times the machine floor's")
      ->check(ocp::cli::positive_real(1e6))
      ->needs(loop->get_option("--compare"));
  loop->add_flag("--fail-on-fault", options.fail_on_fault,
                 "gate: fail (exit 1) when the Streamer raised any fault after the client connected");
  loop->add_option("command", options.command, "client command after `--`; {port} is replaced by the port");
  return loop;
}

namespace {

// The simulated operator's frames fall 1.25 ms after each control tick (see "phases" below).
constexpr Micros operator_phase{1'250};

StreamerSimOptions streamer_options(std::uint16_t port, const std::string& vehicle) {
  StreamerSimOptions options;
  options.vehicle = vehicle;
  options.plugin_params.tcp_port = port;
  options.operator_phase = operator_phase;
  return options;
}

std::string join(const std::vector<std::string>& args) {
  std::string out;
  for (const auto& arg : args) out += (out.empty() ? "" : " ") + arg;
  return out;
}

bool write_file(const std::string& path, const std::string& text) {
  std::ofstream file(path, std::ios::binary);
  file << text;
  return static_cast<bool>(file);
}

}  // namespace

int run_loop(const LoopOptions& options) {
  namespace asio = boost::asio;
  // As the simulators do: no 50 µs default timer slack on the control tick's thread.
  prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
  const bool launch = !options.command.empty();
  const std::uint16_t port = options.port.value_or(launch ? 0 : 4000);

  asio::io_context io;
  AsioExecutor executor(io);
  const LogSink quiet_sink{};   // the simulators' log lines would bury the progress line
  StreamerSimulation simulation(executor, streamer_options(port, "vehicle"), quiet_sink);
  if (auto status = simulation.start(); !status) {
    std::cerr << "ocp_bench loop: cannot start the Streamer: " << status.error().detail << "\n";
    return 1;
  }
  // The Streamer's control tick (and its simulated operator's frame) falls on start + k·10 ms.
  const SimTime start = executor.now();
  LoopRecorder recorder(simulation.streamer().events(), start);

  // --compare: the references run beside the client under test, on the same machine at the same
  // time, so ratios are fair on a busy machine. Phases: nothing else the bench does is scheduled
  // at the moment the client's round trip runs (it used to be: the reference Streamer's tick
  // wrote its control frame right after the one under test and woke the timer client's thread in
  // the middle of its round trip, doubling the measured echo delay). Within each 10 ms period,
  // 1.25 ms apart: the Streamer under test ticks at 0 (its operator's frame at 1.25 ms), the floor
  // sends at 2.5 ms, the bare client's Streamer ticks at 3.75 ms (operator 5 ms), the timer
  // client's at 6.25 ms (operator 7.5 ms), housekeeping runs at 8.75 ms. The timer client answers
  // at a phase that sweeps the whole period (by design), so it meets each of them briefly.
  constexpr Micros floor_phase{2'500};
  constexpr Micros bare_streamer_phase{3'750};
  constexpr Micros timer_streamer_phase{6'250};
  constexpr Micros housekeeping_phase{8'750};
  // A reference client's own Streamer, started at its phase; its recorder exists once started.
  struct Reference {
    std::unique_ptr<StreamerSimulation> simulation;
    std::unique_ptr<LoopRecorder> recorder;
  };
  Reference bare, timer;
  std::unique_ptr<BareClient> bare_client;
  std::unique_ptr<TimerClient> timer_client;
  std::unique_ptr<FloorEcho> floor;
  if (options.compare) {
    bare.simulation = std::make_unique<StreamerSimulation>(executor, streamer_options(0, "bare_vehicle"), quiet_sink);
    timer.simulation = std::make_unique<StreamerSimulation>(executor, streamer_options(0, "timer_vehicle"), quiet_sink);
  }

  ChildProcess child;
  if (launch) {
    std::string error;
    if (!child.start(options.command, simulation.port(), error)) {
      std::cerr << "ocp_bench loop: cannot launch the client: " << error << "\n";
      return 1;
    }
  } else {
    std::cerr << "ocp_bench loop: waiting for a vehicle client on 127.0.0.1:" << simulation.port() << "\n";
  }

  int exit_code = 0;
  std::optional<SimTime> measure_start;
  std::optional<SimTime> measure_end;
  bool stopped = false;
  auto finish = [&](int code) {
    if (stopped) return;
    stopped = true;
    exit_code = code;
    measure_end = executor.now();
    io.stop();
  };
  for (auto [reference, phase] : {std::pair{&bare, bare_streamer_phase}, std::pair{&timer, timer_streamer_phase}}) {
    if (!reference->simulation) continue;
    executor.call_at(start + phase, [&, reference] {
      if (auto status = reference->simulation->start(); !status) {
        std::cerr << "ocp_bench loop: cannot start a reference Streamer: " << status.error().detail << "\n";
        finish(1);
        return;
      }
      reference->recorder = std::make_unique<LoopRecorder>(reference->simulation->streamer().events(), start);
    });
  }
  asio::signal_set signals(io, SIGINT, SIGTERM);
  signals.async_wait([&](const boost::system::error_code& error, int) {
    if (!error) finish(measure_start ? 0 : 1);
  });

  const bool tty = isatty(STDERR_FILENO) == 1;
  const Micros duration{static_cast<std::int64_t>(options.duration_s * 1e6)};
  const Micros connect_timeout{static_cast<std::int64_t>(options.connect_timeout_s * 1e6)};
  SimTime last_progress = start;
  // 10 Hz housekeeping: starts the window at the first connection, watches the child, prints progress.
  PeriodicTimer housekeeping(executor, Micros{100'000}, [&](SimTime now) {
    if (launch && child.poll()) {
      std::cerr << "\nocp_bench loop: the client exited with status " << *child.poll() << "\n";
      finish(1);
      return;
    }
    if (!measure_start) {
      if (recorder.connected_once()) {
        measure_start = now;
        if (options.compare) {
          bare_client = std::make_unique<BareClient>(bare.simulation->port());
          timer_client = std::make_unique<TimerClient>(timer.simulation->port());
          // The floor's grid: floor_phase after a tick of the Streamer under test, ≥ 10 ms ahead.
          const SimTime first_send = now + Micros{10'000} - (now - start) % Micros{10'000} + floor_phase;
          floor = std::make_unique<FloorEcho>(executor.to_steady(first_send));
        }
      } else if (now - start > connect_timeout) {
        std::cerr << "ocp_bench loop: no vehicle client connected within " << options.connect_timeout_s << " s\n";
        finish(1);
      }
      return;
    }
    if (now - *measure_start >= duration) {
      finish(0);
      return;
    }
    if (!options.quiet && now - last_progress >= Micros{1'000'000}) {
      last_progress = now;
      const double elapsed_s = static_cast<double>((now - *measure_start).count()) / 1e6;
      std::cerr << (tty ? "\r" : "")
                << fmt::format("ocp_bench loop: {:.0f}/{:.0f} s, {} responses, {} echoes, {} faults", elapsed_s,
                               options.duration_s, recorder.response_times_s().size(),
                               recorder.echo_delays_us().size(), recorder.faults().size())
                << (tty ? "" : "\n") << std::flush;
    }
  });
  housekeeping.start(start + Micros{100'000} + housekeeping_phase);
  io.run();
  if (tty && !options.quiet) std::cerr << "\n";
  housekeeping.stop();

  // Every path ends the child and the references before the figures are read.
  LoopResult result;
  result.child_exit = launch ? child.poll() : std::nullopt;
  child.stop();
  if (bare_client) bare_client->stop();
  if (timer_client) timer_client->stop();
  if (floor) floor->stop();

  result.command = join(options.command);
  result.port = simulation.port();
  const SimTime window_start = measure_start.value_or(start);
  result.duration_s = static_cast<double>((measure_end.value_or(executor.now()) - window_start).count()) / 1e6;
  const double since_start_s = static_cast<double>((measure_end.value_or(executor.now()) - start).count()) / 1e6;
  result.client = figures_from("client", recorder, since_start_s);
  if (bare.recorder) {
    result.bare_client = figures_from("bare_client (blocking read, answers at once)", *bare.recorder, since_start_s);
  }
  if (timer.recorder) result.timer_client = figures_from("timer_client (answers every 10 ms)", *timer.recorder, since_start_s);
  if (floor) {
    result.floor_echo_delays_us = floor->round_trips_us();
    result.floor_echo_us = summarize(result.floor_echo_delays_us);
  }
  simulation.stop();
  for (Reference* reference : {&bare, &timer}) {
    if (reference->simulation) reference->simulation->stop();
  }

  result.gates = evaluate_gates(options, result);
  print_table(std::cout, result);
  if (exit_code == 0 && !all_passed(result.gates)) exit_code = 1;
  if (!options.json_path.empty() && !write_file(options.json_path, to_json(result))) {
    std::cerr << "ocp_bench loop: cannot write " << options.json_path << "\n";
    exit_code = 1;
  }
  if (!options.html_path.empty() && !write_file(options.html_path, to_html(result))) {
    std::cerr << "ocp_bench loop: cannot write " << options.html_path << "\n";
    exit_code = 1;
  }
  return exit_code;
}

}  // namespace ocp::bench
