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
#include "floor_echo.hpp"
#include "loop_gates.hpp"
#include "loop_recorder.hpp"
#include "loop_report.hpp"
#include "loop_result.hpp"
#include "ocp/asio/executor.hpp"
#include "sim_app/client_process.hpp"
#include "streamer_app/streamer_simulation.hpp"
#include "timer_client.hpp"
#include "ocp/cli_checks.hpp"
#include "ocp/cli_paths.hpp"
#include "ocp/exit_codes.hpp"

namespace ocp::bench {

CLI::App* add_loop_command(CLI::App& app, LoopOptions& options) {
  CLI::App* loop = app.add_subcommand(
      "loop",
      "Measure a vehicle client against a Streamer with a simulated operator on 127.0.0.1:\n"
      "echo delay, responses, OCP latency, tick lateness and faults, from the Streamer's events.\n"
      "  ocp_bench loop --port 4000                       wait for your client on :4000\n"
      "  ocp_bench loop -- ./my_client 127.0.0.1:{port}  launch it ({port} and $OCP_PORT)\n"
      "Always in real time (it has no --time): it measures the client's real speed, which virtual\n"
      "time (docs/virtual-time.md) would hide; ocp_conformance, ocp_scenario and ocp_campaign take --time.");
  loop->add_option("--port", options.port, "Streamer TCP port (default: 4000 when waiting, a free one with a command)");
  loop->add_option("--duration-s", options.duration_s, "measurement time from the client's connection")
      ->capture_default_str()->check(ocp::cli::real(0.1, 86400.0));
  loop->add_option("--connect-timeout-s", options.connect_timeout_s, "give up when no client connects within this")
      ->capture_default_str()->check(ocp::cli::real(0.1, 3600.0));
  loop->add_option("--json", options.json_path, "write the figures as JSON to FILE")->check(ocp::cli::writable_file());
  loop->add_option("--html", options.html_path, "write a self-contained HTML page (inline SVG) to FILE")
      ->check(ocp::cli::writable_file());
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
  loop->add_option("--min-response-rate", options.min_response_rate,
                   "gate: fail (exit 1) when the client sent fewer responses per second than this (the product expects ~100)")
      ->check(ocp::cli::positive_real(1e6));
  loop->add_option("--max-response-gap-ms", options.max_response_gap_ms,
                   "gate: fail (exit 1) when two responses were ever further apart than this (the Streamer closes at 2000)")
      ->check(ocp::cli::positive_real(1e6));
  loop->add_option("--max-latency-p99-ms", options.max_latency_p99_ms,
                   "gate: fail (exit 1) when the Streamer's measured loop latency p99 is above this")
      ->check(ocp::cli::positive_real(1e6));
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
  options.program = "ocp_bench loop";
  options.port_option = "--port N (or leave --port out when launching a client: a free port is used)";
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

// One `ocp_bench loop` run, its steps in the order run_loop calls them. The members are
// declared in the order the run creates them, so that they go in the reverse order: the
// housekeeping and the child before the references, the recorders before their Streamers.
class LoopRun {
 public:
  explicit LoopRun(const LoopOptions& options)
      : options_(options),
        launch_(!options.command.empty()),
        executor_(io_),
        simulation_(executor_, streamer_options(options.port.value_or(launch_ ? 0 : 4000), "vehicle"), quiet_sink_) {}

  // The Streamer under test (its control tick, and its simulated operator's frame, fall on
  // start + k·10 ms from now on) and, with --compare, the references' Streamers, not started yet.
  bool start_streamer() {
    if (auto status = simulation_.start(); !status) {
      std::cerr << "ocp_bench loop: cannot start the Streamer: " << status.error().detail << "\n";
      return false;
    }
    start_ = executor_.now();
    recorder_.emplace(simulation_.streamer().events(), start_);
    if (options_.compare) {
      bare_.simulation = std::make_unique<StreamerSimulation>(executor_, streamer_options(0, "bare_vehicle"), quiet_sink_);
      timer_.simulation = std::make_unique<StreamerSimulation>(executor_, streamer_options(0, "timer_vehicle"), quiet_sink_);
    }
    return true;
  }

  // Launches the client command, or says where the Streamer waits for one.
  bool launch_client() {
    if (!launch_) {
      std::cerr << "ocp_bench loop: waiting for a vehicle client on 127.0.0.1:" << simulation_.port() << "\n";
      return true;
    }
    auto launched = sim_app::ClientProcess::launch(options_.command, simulation_.port(), sim_app::ClientProcess::to_stderr);
    if (!launched) {
      std::cerr << "ocp_bench loop: cannot launch the client: " << launched.error().message() << "\n";
      return false;
    }
    child_ = std::move(*launched);
    return true;
  }

  // Each reference Streamer starts at its own phase of the 10 ms period (see the phases above).
  void start_references_at_their_phases() {
    for (auto [reference, phase] : {std::pair{&bare_, bare_streamer_phase}, std::pair{&timer_, timer_streamer_phase}}) {
      if (!reference->simulation) continue;
      executor_.call_at(start_ + phase, [this, reference] {
        if (auto status = reference->simulation->start(); !status) {
          std::cerr << "ocp_bench loop: cannot start a reference Streamer: " << status.error().detail << "\n";
          finish(ocp::cli::exit_usage_error);
          return;
        }
        reference->recorder = std::make_unique<LoopRecorder>(reference->simulation->streamer().events(), start_);
      });
    }
  }

  // Ctrl-C ends the measurement early: the figures so far are reported, marked interrupted,
  // and the run exits 130.
  void stop_on_signal() {
    signals_.emplace(io_, SIGINT, SIGTERM, SIGHUP);
    signals_->async_wait([this](const boost::system::error_code& error, int) {
      if (error) return;
      interrupted_ = true;
      finish(ocp::cli::exit_interrupted);
    });
  }

  // Runs until finish(): the duration has passed, the client exited, no client came, a
  // reference failed or a signal came.
  void measure() {
    last_progress_ = start_;
    housekeeping_.emplace(executor_, Micros{100'000}, [this](SimTime now) { housekeeping(now); });
    housekeeping_->start(start_ + Micros{100'000} + housekeeping_phase);
    io_.run();
    if (tty_ && !options_.quiet) std::cerr << "\n";
    housekeeping_->stop();
  }

  // Every path ends the child and the references before the figures are read.
  LoopResult take_result() {
    LoopResult result;
    result.interrupted = interrupted_;
    result.child_exit = child_exit();
    child_.reset();   // kills it if it still runs
    if (bare_client_) bare_client_->stop();
    if (timer_client_) timer_client_->stop();
    if (floor_) floor_->stop();

    result.command = join(options_.command);
    result.port = simulation_.port();
    const SimTime window_start = measure_start_.value_or(start_);
    result.duration_s = static_cast<double>((measure_end_.value_or(executor_.now()) - window_start).count()) / 1e6;
    const double since_start_s = static_cast<double>((measure_end_.value_or(executor_.now()) - start_).count()) / 1e6;
    result.client = figures_from("client", *recorder_, since_start_s);
    if (bare_.recorder) {
      result.bare_client = figures_from("bare_client (blocking read, answers at once)", *bare_.recorder, since_start_s);
    }
    if (timer_.recorder) result.timer_client = figures_from("timer_client (answers every 10 ms)", *timer_.recorder, since_start_s);
    if (floor_) {
      result.floor_echo_delays_us = floor_->round_trips_us();
      result.floor_echo_us = summarize(result.floor_echo_delays_us);
    }
    simulation_.stop();
    for (Reference* reference : {&bare_, &timer_}) {
      if (reference->simulation) reference->simulation->stop();
    }
    return result;
  }

  // The table, the gates (a failed one fails the run), and the --json and --html files.
  int report(LoopResult& result) {
    int exit_code = exit_code_;
    result.gates = evaluate_gates(options_, result);
    print_table(std::cout, result);
    if (exit_code == 0 && !all_passed(result.gates)) exit_code = 1;
    if (!options_.json_path.empty() && !write_file(options_.json_path, to_json(result))) {
      std::cerr << "ocp_bench loop: cannot write " << options_.json_path << "\n";
      exit_code = ocp::cli::exit_usage_error;
    }
    if (!options_.html_path.empty() && !write_file(options_.html_path, to_html(result))) {
      std::cerr << "ocp_bench loop: cannot write " << options_.html_path << "\n";
      exit_code = ocp::cli::exit_usage_error;
    }
    if (interrupted_) std::cerr << "ocp_bench loop: interrupted\n";
    return exit_code;
  }

 private:
  // Ends the run (the first call decides the exit code).
  void finish(int code) {
    if (stopped_) return;
    stopped_ = true;
    exit_code_ = code;
    measure_end_ = executor_.now();
    io_.stop();
  }

  // 10 Hz: starts the window at the first connection, watches the child, prints progress.
  void housekeeping(SimTime now) {
    if (const auto exited = child_exit()) {
      // Before it connected, the client could not be measured at all: a harness error.
      std::cerr << "\nocp_bench loop: the client exited with status " << *exited
                << (measure_start_ ? "" : " before it connected") << "\n";
      finish(measure_start_ ? 1 : ocp::cli::exit_usage_error);
      return;
    }
    if (!measure_start_) {
      await_client(now);
      return;
    }
    if (now - *measure_start_ >= duration_) {
      finish(0);
      return;
    }
    if (!options_.quiet && now - last_progress_ >= Micros{1'000'000}) print_progress(now);
  }

  // The measurement window opens at the client's first connection; with --compare the
  // reference clients and the floor start then too, so that all of them share the window.
  void await_client(SimTime now) {
    if (recorder_->connected_once()) {
      measure_start_ = now;
      if (options_.compare) {
        bare_client_ = std::make_unique<BareClient>(bare_.simulation->port());
        timer_client_ = std::make_unique<TimerClient>(timer_.simulation->port());
        // The floor's grid: floor_phase after a tick of the Streamer under test, ≥ 10 ms ahead.
        const SimTime first_send = now + Micros{10'000} - (now - start_) % Micros{10'000} + floor_phase;
        floor_ = std::make_unique<FloorEcho>(executor_.to_steady(first_send));
      }
    } else if (now - start_ > connect_timeout_) {
      std::cerr << "ocp_bench loop: no vehicle client connected within " << options_.connect_timeout_s << " s\n";
      finish(ocp::cli::exit_usage_error);
    }
  }

  // Once a second; on a terminal the line overwrites itself.
  void print_progress(SimTime now) {
    last_progress_ = now;
    const double elapsed_s = static_cast<double>((now - *measure_start_).count()) / 1e6;
    std::cerr << (tty_ ? "\r" : "")
              << fmt::format("ocp_bench loop: {:.0f}/{:.0f} s, {} responses, {} echoes, {} faults", elapsed_s,
                             options_.duration_s, recorder_->response_times_s().size(),
                             recorder_->echo_delays_us().size(), recorder_->faults().size())
              << (tty_ ? "" : "\n") << std::flush;
  }

  const LoopOptions& options_;
  const bool launch_;
  const bool tty_ = isatty(STDERR_FILENO) == 1;
  const Micros duration_{static_cast<std::int64_t>(options_.duration_s * 1e6)};
  const Micros connect_timeout_{static_cast<std::int64_t>(options_.connect_timeout_s * 1e6)};
  boost::asio::io_context io_;
  AsioExecutor executor_;
  const LogSink quiet_sink_{};   // the simulators' log lines would bury the progress line
  StreamerSimulation simulation_;
  SimTime start_{0};
  std::optional<LoopRecorder> recorder_;
  Reference bare_, timer_;
  std::unique_ptr<BareClient> bare_client_;
  std::unique_ptr<TimerClient> timer_client_;
  std::unique_ptr<FloorEcho> floor_;
  std::unique_ptr<sim_app::ClientProcess> child_;   // null until launched (or when waiting for one)
  // The client's exit status (the code, or 128 + signal) once it ended; nullopt while it runs.
  std::optional<int> child_exit() { return child_ && !child_->running() ? child_->exit_status() : std::nullopt; }
  int exit_code_ = 0;
  bool interrupted_ = false;
  std::optional<SimTime> measure_start_;
  std::optional<SimTime> measure_end_;
  bool stopped_ = false;
  std::optional<boost::asio::signal_set> signals_;
  SimTime last_progress_{0};
  std::optional<PeriodicTimer> housekeeping_;
};

}  // namespace

int run_loop(const LoopOptions& options) {
  // As the simulators do: no 50 µs default timer slack on the control tick's thread.
  prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
  LoopRun run(options);
  if (!run.start_streamer() || !run.launch_client()) return ocp::cli::exit_usage_error;
  run.start_references_at_their_phases();
  run.stop_on_signal();
  run.measure();
  LoopResult result = run.take_result();
  return run.report(result);
}

}  // namespace ocp::bench
