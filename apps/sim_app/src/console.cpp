#include "sim_app/console.hpp"

#include <optional>

namespace ocp::sim_app {

StatusTicker::StatusTicker(Executor& executor, Micros period, std::function<void()> report)
    : executor_(executor),
      timer_(executor, period, [this](SimTime) {
        if (report_) report_();
      }),
      report_(std::move(report)) {}

void StatusTicker::start() { timer_.start(executor_.now() + timer_.period()); }
void StatusTicker::stop() { timer_.stop(); }

std::string format_latency(const std::optional<std::uint64_t>& latency_ms) {
  return latency_ms ? std::to_string(*latency_ms) + " ms" : std::string("n/a");
}

std::string format_faults(const FaultSet& faults) {
  if (faults.empty()) return "none";
  std::string text;
  for (const auto& identifier : faults.identifiers()) text += (text.empty() ? "" : ",") + identifier;
  return text;
}

double per_second(std::uint64_t count_now, std::uint64_t count_before, Micros elapsed) {
  if (elapsed.count() <= 0 || count_now < count_before) return 0.0;
  return static_cast<double>(count_now - count_before) * 1e6 / static_cast<double>(elapsed.count());
}

}  // namespace ocp::sim_app
