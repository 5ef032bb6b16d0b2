#include "fleet_command.hpp"

#include <fmt/format.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <fstream>
#include <iostream>
#include <optional>

#include "fleet_point.hpp"
#include "fleet_threads_report.hpp"
#include "json_text.hpp"
#include "kernel_floor.hpp"
#include "ocp/faults.hpp"
#include "svg_chart.hpp"
#include "ocp/cli_checks.hpp"
#include "ocp/cli_paths.hpp"
#include "ocp/exit_codes.hpp"
#include "ocp/interrupt.hpp"

namespace ocp::bench {

CLI::App* add_fleet_command(CLI::App& app, FleetOptions& options) {
  CLI::App* fleet = app.add_subcommand(
      "fleet",
      "Scale curve: N Streamers with N reference clients in one process over loopback TCP at 100 Hz,\n"
      "and N vehicles in virtual time (in-memory pipes). Each point runs in its own child process.");
  fleet->add_option("--loopback", options.loopback_vehicles, "vehicle counts over loopback TCP (0: none)")
      ->delimiter(',')->capture_default_str()->check(CLI::Range(0, 100000));
  fleet->add_option("--virtual", options.virtual_vehicles, "vehicle counts in virtual time (0: none)")
      ->delimiter(',')->capture_default_str()->check(CLI::Range(0, 100000));
  fleet->add_option("--window-s", options.window_s, "loopback: wall seconds measured per point (after --warm-up-s)")
      ->capture_default_str()->check(ocp::cli::real(0.1, 3600.0));
  fleet->add_option("--simulated-s", options.simulated_s, "virtual: simulated seconds measured per point")
      ->capture_default_str()->check(ocp::cli::real(0.1, 36000.0));
  fleet->add_option("--warm-up-s", options.warm_up_s, "run this long (wall or simulated) before measuring")
      ->capture_default_str()->check(ocp::cli::real(0.0, 600.0));
  fleet->add_option("--point-timeout-s", options.point_timeout_s, "kill a point that runs longer than this")
      ->capture_default_str()->check(ocp::cli::real(1.0, 86400.0));
  fleet->add_flag("--unobserved", options.unobserved,
                  "virtual points: do not subscribe to events (observing decodes every frame's pair)");
  fleet->add_option("--streamer-threads", options.streamer_threads,
                    "loopback: threads the Streamers are spread over; the Player keeps the main thread (0: all on it)")
      ->capture_default_str()->check(CLI::Range(0, 64));
  fleet->add_option("--client-threads", options.client_threads,
                    "loopback: threads the reference clients are spread over, each with its own io_context\n"
                    "(default: as many as --streamer-threads, at least 1; 0: each client on its own Streamer's thread,\n"
                    "both ends of its traffic on one thread)")
      ->check(CLI::Range(0, 64));
  fleet->add_option("--tick-slots", options.tick_slots,
                    "loopback: one shared control ticker per thread with this many slots over the 10 ms period\n"
                    "(0: a timer per Streamer; default: one slot per 10 vehicles of a Streamer thread, 1 to 10)")
      ->check(CLI::Range(0, 10000));
  fleet->add_flag("--no-kernel-floor{false}", options.kernel_floor,
                  "loopback points: skip the kernel floors (the kernel's TCP cost of the same traffic, no simulator:\n"
                  "batched on one thread, then paced as the point paces it; measured after the point's window)");
  fleet->add_flag("--no-codec-floor{false}", options.codec_floor,
                  "virtual points: skip the codec floor (the wire codec and MAC work of the same fleet alone,\n"
                  "measured after the point's window)");
  fleet->add_flag("--in-process", options.in_process, "run the points in this process, not forked children (for profilers)");
  fleet->add_option("--json", options.json_path, "write the points as JSON to FILE")->check(ocp::cli::writable_file());
  fleet->add_option("--svg", options.svg_path, "write the scale curve as SVG to FILE")->check(ocp::cli::writable_file());
  return fleet;
}

namespace {

// Runs one point in a forked child (clean CPU and RSS figures; a point that hangs or crashes
// is killed and reported instead of taking the whole run down).
//
// Why a fork without exec here, and not the one launcher of other programs
// (sim_app::ClientProcess, tests/support/child_process.hpp): what runs in the child is a
// function of this program, run_fleet_point, not another program, so there is nothing to
// exec. The two hazards that launcher guards against do not arise: no environment is set
// between fork and exec (there is no exec, and the child changes no environment), and the
// parent is single-threaded when it forks (it runs no thread of its own between points; the
// point's executor threads start in the child), so no lock can be held by a thread the child
// lacks. It holds no listening socket either, and the pipe's ends are closed on both sides
// before the next point, so no point inherits another's descriptors.
FleetPointResult run_in_child(const FleetPointOptions& options, double timeout_s) {
  FleetPointResult result;
  result.mode = options.mode;
  result.vehicles = options.vehicles;
  int fds[2];
  if (pipe(fds) != 0) {
    std::snprintf(result.error, sizeof result.error, "pipe failed");
    return result;
  }
  std::cout.flush();
  std::cerr.flush();
  const pid_t pid = fork();
  if (pid < 0) {
    std::snprintf(result.error, sizeof result.error, "fork failed");
    return result;
  }
  if (pid == 0) {
    close(fds[0]);
    // The point itself does not watch for Ctrl-C: the parent kills it (below).
    signal(SIGINT, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
    const FleetPointResult child_result = run_fleet_point(options);
    const auto* bytes = reinterpret_cast<const char*>(&child_result);
    std::size_t written = 0;
    while (written < sizeof child_result) {
      const ssize_t n = write(fds[1], bytes + written, sizeof child_result - written);
      if (n <= 0) break;
      written += static_cast<std::size_t>(n);
    }
    _exit(0);
  }
  close(fds[1]);
  FleetPointResult received;
  auto* bytes = reinterpret_cast<char*>(&received);
  std::size_t got = 0;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  bool timed_out = false;
  bool interrupted = false;
  while (got < sizeof received) {
    if (ocp::cli::interrupt_requested()) {
      interrupted = true;
      break;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(give_up - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      timed_out = true;
      break;
    }
    pollfd poll_fd{fds[0], POLLIN, 0};
    if (poll(&poll_fd, 1, static_cast<int>(std::min<long>(left.count(), 1000))) <= 0) continue;
    const ssize_t n = read(fds[0], bytes + got, sizeof received - got);
    if (n <= 0) break;
    got += static_cast<std::size_t>(n);
  }
  close(fds[0]);
  if (timed_out || interrupted) kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  if (got == sizeof received) return received;
  std::snprintf(result.error, sizeof result.error, "%s",
                interrupted ? "interrupted"
                : timed_out ? fmt::format("did not finish within {:g} s (killed)", timeout_s).c_str()
                            : fmt::format("child ended without a result (status {})", status).c_str());
  return result;
}

// What one more vehicle costs: the slope of resident memory between this point and the previous
// one of the same mode. The fixed cost (io_context, Player, allocator arenas) dominates the
// plain per-vehicle figure at small N; the slope does not contain it.
void set_marginal_memory(std::vector<FleetPointResult>& points) {
  FleetPointResult& last = points.back();
  if (!last.ok) return;
  for (auto previous = points.rbegin() + 1; previous != points.rend(); ++previous) {
    if (!previous->ok || previous->mode != last.mode || previous->vehicles >= last.vehicles) continue;
    const double grown_kib = (last.rss_end_kib - last.rss_base_kib) - (previous->rss_end_kib - previous->rss_base_kib);
    last.marginal_kib_per_vehicle = grown_kib / (last.vehicles - previous->vehicles);
    return;
  }
  last.marginal_kib_per_vehicle = last.kib_per_vehicle;
}

std::string fault_summary(const FleetPointResult& point) {
  std::string out;
  for (std::size_t id = 0; id < fault_count; ++id) {
    if (point.faults_raised[id] == 0) continue;
    if (!out.empty()) out += " ";
    out += fmt::format("{}×{}", fault_identifier(static_cast<FaultId>(id)), point.faults_raised[id]);
  }
  return out.empty() ? "none" : out;
}

void print_header(std::ostream& out) {
  out << fmt::format("{:<9} {:>6} {:>6} {:>9} {:>9} {:>9} {:>9} {:>9} {:>10} {:>10} {:>9} {:>9} {:>9}  {}\n", "mode", "N",
                     "ticks", "tick p50", "tick p99", "tick max", "echo p50", "echo p99", "CPU s/s", "floor", "sim/wall",
                     "KiB/veh", "marginal", "faults raised");
  out << fmt::format("{:<9} {:>6} {:>6} {:>9} {:>9} {:>9} {:>9} {:>9} {:>10} {:>10} {:>9} {:>9} {:>9}\n", "", "", "run %", "µs",
                     "µs", "µs", "µs", "µs", "(CPU/sim)", "CPU s/s", "", "", "KiB/veh");
}

// Control ticks that ran ÷ those due (N × 100 Hz over the window). A saturated executor
// skips ticks more than a period late (PeriodicTimer, ControlTicker): the lateness
// percentiles cover only the ticks that ran, so this is the column that shows saturation.
// A window's two edges can both hold a tick of the same vehicle, one more than window × 100 Hz:
// the share is capped at 1, since running every tick due is all a point can do.
double ticks_run_share(const FleetPointResult& point) {
  const double due = point.window_s * point.vehicles * 100.0;
  return due > 0 ? std::min(1.0, static_cast<double>(point.ticks) / due) : 0.0;
}

// The point's CPU (all threads) per control tick that ran, in µs; 0 when none ran.
double cpu_us_per_vehicle_tick(const FleetPointResult& point) {
  return point.ticks ? point.cpu_s * 1e6 / static_cast<double>(point.ticks) : 0.0;
}

void print_point(std::ostream& out, const FleetPointResult& point) {
  if (!point.ok) {
    out << fmt::format("{:<9} {:>6}  failed: {}\n", fleet_mode_name(point.mode), point.vehicles, point.error);
    return;
  }
  const std::string mode = fleet_mode_name(point.mode) + (point.observed ? "" : "*");
  // Loopback: the kernel's TCP alone; virtual: the codec alone (print_floors says which).
  const std::string floor = point.kernel_floor_measured  ? fmt::format("{:.3f}", point.kernel_floor_cpu_per_s)
                            : point.codec_floor_measured ? fmt::format("{:.3f}", point.codec_floor_cpu_per_s)
                                                         : "-";
  out << fmt::format("{:<9} {:>6} {:>6.1f} {:>9.0f} {:>9.0f} {:>9.0f} {:>9.0f} {:>9.0f} {:>10.3f} {:>10} {:>9.2f} {:>9.1f} {:>9.1f}  {}\n",
                     mode, point.vehicles, 100.0 * ticks_run_share(point), point.tick_p50_us, point.tick_p99_us,
                     point.tick_max_us, point.echo_p50_us, point.echo_p99_us, point.cpu_per_simulated_s, floor,
                     point.simulated_per_wall_s, point.kib_per_vehicle, point.marginal_kib_per_vehicle,
                     fault_summary(point));
}

// The floors against the machine and the point: how much of the cores the kernel's TCP alone
// takes (loopback), how much of the point's CPU the codec alone is (virtual).
void print_floors(std::ostream& out, const std::vector<FleetPointResult>& points, int cores) {
  for (const auto& point : points) {
    if (!point.ok) continue;
    const std::string name = fmt::format("{} N={}", fleet_mode_name(point.mode), point.vehicles);
    if (point.kernel_floor_measured) {
      out << fmt::format(
          "{}: kernel TCP alone (one thread, {:.0f}-byte frames out, {:.0f} back, no simulator): {:.1f} µs CPU per "
          "vehicle-tick = {:.3g} CPU s/s of {} cores ({:.0f} %); the point used {:.3g} CPU s/s and ran {:.1f} % of its ticks, "
          "{:.1f} µs CPU per vehicle-tick run ({:.1f}× the floor)\n",
          name, point.control_bytes, point.response_bytes, point.kernel_floor_us_per_vehicle_tick,
          point.kernel_floor_cpu_per_s, cores, 100.0 * point.kernel_floor_cpu_per_s / cores, point.cpu_per_simulated_s,
          100.0 * ticks_run_share(point), cpu_us_per_vehicle_tick(point),
          cpu_us_per_vehicle_tick(point) / point.kernel_floor_us_per_vehicle_tick);
    }
    if (point.paced_floor_measured) {
      const PacedShape shape = paced_floor_shape(point.vehicles, point.streamer_threads, point.client_threads,
                                                 point.control_tick_slots);
      const int threads = shape.server_threads;
      const int bursts = shape.slots;
      const std::string against_batched =
          point.kernel_floor_measured
              ? fmt::format(" ({:.1f}× the batched floor)",
                            point.paced_floor_us_per_vehicle_tick / point.kernel_floor_us_per_vehicle_tick)
              : "";
      out << fmt::format(
          "{}: kernel TCP paced as the point ({} server thread{}, {} burst{} each per 10 ms, the clients' ends on {}): "
          "{:.1f} µs CPU per vehicle-tick = {:.3g} CPU s/s{}; the point ran at {:.1f}× this\n",
          name, threads, threads == 1 ? "" : "s", bursts, bursts == 1 ? "" : "s",
          shape.client_threads_of_their_own ? "threads of their own" : "the server threads",
          point.paced_floor_us_per_vehicle_tick, point.paced_floor_cpu_per_s, against_batched,
          cpu_us_per_vehicle_tick(point) / point.paced_floor_us_per_vehicle_tick);
    }
    if (point.codec_floor_measured) {
      out << fmt::format(
          "{}: codec alone (control encode + decode, response encode + decode, MAC issue + verify): {:.2f} µs CPU per "
          "vehicle cycle = {:.3g} CPU s per simulated s ({:.0f} % of the point's {:.3g})\n",
          name, point.codec_floor_us_per_vehicle_cycle, point.codec_floor_cpu_per_s,
          100.0 * point.codec_floor_cpu_per_s / point.cpu_per_simulated_s, point.cpu_per_simulated_s);
    }
    const std::pair<const char*, const char*> errors[] = {{"kernel", point.kernel_floor_error},
                                                          {"paced kernel", point.paced_floor_error},
                                                          {"codec", point.codec_floor_error}};
    for (const auto& [floor, error] : errors) {
      if (error[0] != '\0') out << fmt::format("{}: {} floor not measured: {}\n", name, floor, error);
    }
  }
}

std::string optional_number(bool present, double value) { return present ? json_number(value) : "null"; }
std::string optional_string(const char* text) { return text[0] != '\0' ? json_string(text) : "null"; }

std::string point_json(const FleetPointResult& point) {
  std::string faults = "{";
  for (std::size_t id = 0; id < fault_count; ++id) {
    if (point.faults_raised[id] == 0) continue;
    if (faults.size() > 1) faults += ",";
    faults += fmt::format("{}:{}", json_string(fault_identifier(static_cast<FaultId>(id))), point.faults_raised[id]);
  }
  faults += "}";
  return fmt::format(
      R"({{"mode":"{}","vehicles":{},"streamer_threads":{},"client_threads":{},"tick_slots":{},"observed":{},"ok":{},"error":{},"window_s":{},"wall_s":{},"cpu_s":{},"cpu_per_simulated_s":{},)"
      R"("simulated_per_wall_s":{},"rss_base_kib":{},"rss_end_kib":{},"kib_per_vehicle":{},"marginal_kib_per_vehicle":{},"tick_lateness_us":{{"p50":{},"p99":{},"max":{},"count":{}}},"ticks_run_share":{},)"
      R"("echo_delay_us":{{"p50":{},"p99":{},"count":{}}},"responses":{},"connections":{},"faults_raised":{},)"
      R"("cpu_us_per_vehicle_tick":{},"threads":{},)"
      R"("control_bytes":{},"response_bytes":{},"kernel_floor_cpu_per_s":{},"kernel_floor_us_per_vehicle_tick":{},"kernel_floor_error":{},)"
      R"("paced_floor_cpu_per_s":{},"paced_floor_us_per_vehicle_tick":{},"paced_floor_wall_s":{},"paced_floor_error":{},)"
      R"("codec_floor_cpu_per_simulated_s":{},"codec_floor_us_per_vehicle_cycle":{},"codec_floor_error":{}}})",
      fleet_mode_name(point.mode), point.vehicles, point.streamer_threads, point.client_threads,
      point.control_tick_slots, point.observed, point.ok, json_string(point.error), json_number(point.window_s),
      json_number(point.wall_s), json_number(point.cpu_s), json_number(point.cpu_per_simulated_s),
      json_number(point.simulated_per_wall_s), json_number(point.rss_base_kib), json_number(point.rss_end_kib),
      json_number(point.kib_per_vehicle), json_number(point.marginal_kib_per_vehicle), json_number(point.tick_p50_us),
      json_number(point.tick_p99_us), json_number(point.tick_max_us), point.ticks, json_number(ticks_run_share(point)),
      json_number(point.echo_p50_us), json_number(point.echo_p99_us), point.echoes, point.responses, point.connections,
      faults, optional_number(point.mode == FleetMode::loopback && point.ticks > 0, cpu_us_per_vehicle_tick(point)),
      threads_json(point), json_number(point.control_bytes), json_number(point.response_bytes),
      optional_number(point.kernel_floor_measured, point.kernel_floor_cpu_per_s),
      optional_number(point.kernel_floor_measured, point.kernel_floor_us_per_vehicle_tick),
      optional_string(point.kernel_floor_error),
      optional_number(point.paced_floor_measured, point.paced_floor_cpu_per_s),
      optional_number(point.paced_floor_measured, point.paced_floor_us_per_vehicle_tick),
      optional_number(point.paced_floor_measured, point.paced_floor_wall_s), optional_string(point.paced_floor_error),
      optional_number(point.codec_floor_measured, point.codec_floor_cpu_per_s),
      optional_number(point.codec_floor_measured, point.codec_floor_us_per_vehicle_cycle),
      optional_string(point.codec_floor_error));
}

// Three charts stacked in one SVG file.
std::string scale_svg(const std::vector<FleetPointResult>& points, int cores) {
  auto series = [&](FleetMode mode, const std::string& name, const std::string& color, auto value) {
    XySeries one{name, color, {}, false};
    for (const auto& point : points) {
      if (point.ok && point.mode == mode) one.points.push_back({static_cast<double>(point.vehicles), value(point)});
    }
    return one;
  };
  XySeries kernel_floor = series(FleetMode::loopback, "kernel TCP alone", "#17becf",
                                 [](auto& p) { return p.kernel_floor_measured ? p.kernel_floor_cpu_per_s : 0.0; });
  XySeries paced_floor = series(FleetMode::loopback, "kernel TCP paced", "#9467bd",
                                [](auto& p) { return p.paced_floor_measured ? p.paced_floor_cpu_per_s : 0.0; });
  XySeries codec_floor = series(FleetMode::virtual_time, "codec alone", "#bcbd22",
                                [](auto& p) { return p.codec_floor_measured ? p.codec_floor_cpu_per_s : 0.0; });
  // Each legend entry its own colour (a floor beside its mode): dashes alone are hard to tell
  // apart in a small legend.
  kernel_floor.dashed = paced_floor.dashed = codec_floor.dashed = true;
  // The machine's cores as a horizontal line across the vehicle counts plotted.
  XySeries core_line{fmt::format("{} cores", cores), "#7f7f7f", {}, false, true};
  for (const auto& point : points) {
    if (!point.ok) continue;
    const double vehicles = static_cast<double>(point.vehicles);
    if (core_line.points.empty()) core_line.points = {{vehicles, static_cast<double>(cores)}, {vehicles, static_cast<double>(cores)}};
    core_line.points.front().x = std::min(core_line.points.front().x, vehicles);
    core_line.points.back().x = std::max(core_line.points.back().x, vehicles);
  }
  ChartOptions latency;
  latency.title = "Loopback, 100 Hz per vehicle: tick lateness and echo delay";
  latency.x_label = "vehicles in one process (log)";
  latency.y_label = "µs (log)";
  latency.log_x = latency.log_y = true;
  ChartOptions cpu;
  cpu.title = "CPU seconds per simulated second (whole process, all threads)";
  cpu.x_label = "vehicles (log)";
  cpu.y_label = "CPU s / simulated s (log)";
  cpu.log_x = cpu.log_y = true;
  ChartOptions memory;
  memory.title = "Resident memory per vehicle (whole process ÷ N, and marginal)";
  memory.x_label = "vehicles (log)";
  memory.y_label = "KiB per vehicle (log)";
  memory.log_x = memory.log_y = true;
  const std::vector<std::string> charts{
      xy_chart({series(FleetMode::loopback, "tick lateness p99", "#d62728", [](auto& p) { return p.tick_p99_us; }),
                series(FleetMode::loopback, "tick lateness p50", "#ff9896", [](auto& p) { return p.tick_p50_us; }),
                series(FleetMode::loopback, "echo delay p99", "#1f77b4", [](auto& p) { return p.echo_p99_us; })},
               latency),
      xy_chart(
          {series(FleetMode::loopback, "loopback", "#1f77b4", [](auto& p) { return p.cpu_per_simulated_s; }),
           series(FleetMode::virtual_time, "virtual time", "#2ca02c", [](auto& p) { return p.cpu_per_simulated_s; }),
           kernel_floor, paced_floor, codec_floor, core_line},
          cpu),
      xy_chart({series(FleetMode::loopback, "loopback ÷ N", "#1f77b4", [](auto& p) { return p.kib_per_vehicle; }),
                series(FleetMode::loopback, "loopback marginal", "#aec7e8",
                       [](auto& p) { return p.marginal_kib_per_vehicle; }),
                series(FleetMode::virtual_time, "virtual ÷ N", "#2ca02c", [](auto& p) { return p.kib_per_vehicle; }),
                series(FleetMode::virtual_time, "virtual marginal", "#98df8a",
                       [](auto& p) { return p.marginal_kib_per_vehicle; })},
               memory)};
  const int height = 300;
  std::string svg = fmt::format(
      R"(<svg xmlns="http://www.w3.org/2000/svg" width="760" height="{0}" viewBox="0 0 760 {0}">)" "\n",
      height * static_cast<int>(charts.size()));
  for (std::size_t index = 0; index < charts.size(); ++index) {
    std::string chart = charts[index];
    chart.replace(0, 4, fmt::format("<svg y=\"{}\"", height * static_cast<int>(index)));
    svg += chart;
  }
  return svg + "</svg>\n";
}

}  // namespace

// Seconds of floor rounds after each point: ~30 rounds of 1 000 vehicles (a few % apart from
// run to run), short beside the point itself.
constexpr double floor_s = 0.4;

int auto_tick_slots(int vehicles, int streamer_threads) {
  const int executors = std::max(1, streamer_threads);
  const int per_executor = (std::max(vehicles, 1) + executors - 1) / executors;
  return std::clamp((per_executor + vehicles_per_tick_slot - 1) / vehicles_per_tick_slot, 1, max_auto_tick_slots);
}

int run_fleet(const FleetOptions& options) {
  std::vector<FleetPointOptions> plan;
  for (const int vehicles : options.loopback_vehicles) {
    if (vehicles == 0) continue;
    plan.push_back({FleetMode::loopback, vehicles, options.warm_up_s, options.window_s, 60.0, true, options.streamer_threads,
                    options.client_threads.value_or(std::max(1, options.streamer_threads)),
                    static_cast<std::size_t>(options.tick_slots.value_or(auto_tick_slots(vehicles, options.streamer_threads))),
                    options.kernel_floor ? floor_s : 0.0, 0.0});
  }
  for (const int vehicles : options.virtual_vehicles) {
    if (vehicles == 0) continue;
    plan.push_back({FleetMode::virtual_time, vehicles, options.warm_up_s, options.simulated_s, 60.0, !options.unobserved, 0, 0, 0,
                    0.0, options.codec_floor ? floor_s : 0.0});
  }
  const int cores = usable_cores();
  // Ctrl-C ends the curve after the points measured so far (the one in progress is killed);
  // they are printed and written, marked interrupted, and the exit code is 130.
  if (!options.in_process) ocp::cli::install_interrupt_handlers();
  print_header(std::cout);
  std::vector<FleetPointResult> points;
  for (const auto& point_options : plan) {
    if (ocp::cli::interrupt_requested()) break;
    points.push_back(options.in_process ? run_fleet_point(point_options)
                                        : run_in_child(point_options, options.point_timeout_s));
    set_marginal_memory(points);
    if (ocp::cli::interrupt_requested()) {
      points.pop_back();   // killed half-way: no figures
      break;
    }
    print_point(std::cout, points.back());
    std::cout.flush();
  }
  const bool interrupted = ocp::cli::interrupt_requested();
  if (interrupted) std::cout << "interrupted: " << points.size() << " of " << plan.size() << " points measured before Ctrl-C\n";
  print_floors(std::cout, points, cores);
  for (const auto& point : points) print_thread_table(std::cout, point);
  if (options.unobserved) std::cout << "* unobserved: no event subscription, so no latency or fault figures\n";
  int exit_code = interrupted ? ocp::cli::exit_interrupted : ocp::cli::exit_ok;
  if (!options.json_path.empty()) {
    std::string json = fmt::format(R"({{"tool":"ocp_bench fleet","cores":{},"interrupted":{},"points":[)", cores, interrupted);
    for (std::size_t index = 0; index < points.size(); ++index) json += (index ? "," : "") + point_json(points[index]);
    std::ofstream file(options.json_path);
    file << json << "]}\n";
    if (!file) exit_code = ocp::cli::exit_usage_error;
  }
  if (!options.svg_path.empty()) {
    std::ofstream file(options.svg_path);
    file << scale_svg(points, cores);
    if (!file) exit_code = ocp::cli::exit_usage_error;
  }
  return exit_code;
}

}  // namespace ocp::bench
