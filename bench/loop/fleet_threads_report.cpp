#include "fleet_threads_report.hpp"

#include <fmt/format.h>

#include "json_text.hpp"

namespace ocp::bench {

namespace {

double per_wall_s(const FleetPointResult& point, double value) { return point.wall_s > 0 ? value / point.wall_s : 0.0; }

const ThreadSample* busiest(const FleetPointResult& point) {
  const ThreadSample* top = nullptr;
  for (int index = 0; index < point.thread_count; ++index) {
    if (top == nullptr || point.threads[index].cpu_s > top->cpu_s) top = &point.threads[index];
  }
  return top;
}

bool saturated(const FleetPointResult& point, const ThreadSample& thread) {
  return per_wall_s(point, thread.cpu_s + thread.wait_s) >= saturated_share;
}

}  // namespace

void print_thread_table(std::ostream& out, const FleetPointResult& point) {
  if (!point.ok || point.thread_count == 0) return;
  out << fmt::format("{} N={}: each thread over the {:.3g} s window (per wall second; CPU 1.00 = a whole core)\n",
                     fleet_mode_name(point.mode), point.vehicles, point.wall_s);
  out << fmt::format("  {:<16} {:>8} {:>12} {:>10} {:>12}\n", "thread", "CPU s/s", "waiting s/s", "sleeps/s", "pre-empted/s");
  for (int index = 0; index < point.thread_count; ++index) {
    const ThreadSample& thread = point.threads[index];
    out << fmt::format("  {:<16} {:>8.3f} {:>12.3f} {:>10.0f} {:>12.0f}{}\n", thread.name, per_wall_s(point, thread.cpu_s),
                       per_wall_s(point, thread.wait_s), per_wall_s(point, static_cast<double>(thread.voluntary_switches)),
                       per_wall_s(point, static_cast<double>(thread.involuntary_switches)),
                       saturated(point, thread) ? "  saturated" : "");
  }
  const ThreadSample* top = busiest(point);
  out << fmt::format("  busiest: {} at {:.2f} of a core{} ({:.0f} % of the process's CPU)\n", top->name,
                     per_wall_s(point, top->cpu_s), saturated(point, *top) ? ", saturated" : "",
                     point.cpu_s > 0 ? 100.0 * top->cpu_s / point.cpu_s : 0.0);
}

std::string threads_json(const FleetPointResult& point) {
  std::string json = "[";
  for (int index = 0; index < point.thread_count; ++index) {
    const ThreadSample& thread = point.threads[index];
    json += fmt::format(
        R"({}{{"name":{},"cpu_s":{},"cpu_per_wall_s":{},"waiting_s":{},"voluntary_switches":{},"involuntary_switches":{},"saturated":{}}})",
        index ? "," : "", json_string(thread.name), json_number(thread.cpu_s), json_number(per_wall_s(point, thread.cpu_s)),
        json_number(thread.wait_s), thread.voluntary_switches, thread.involuntary_switches, saturated(point, thread));
  }
  return json + "]";
}

}  // namespace ocp::bench
