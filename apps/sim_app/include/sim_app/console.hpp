#pragma once
// The once-per-second status line of the simulator executables and its formatting helpers.
// (Log records go to the console through ocp::make_console_sink.)
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "ocp/executor.hpp"
#include "ocp/faults.hpp"
#include "ocp/log.hpp"

namespace ocp::sim_app {

// Calls `report` every `period` (absolute deadlines) starting one period from start().
class StatusTicker {
 public:
  StatusTicker(Executor& executor, Micros period, std::function<void()> report);
  void start();
  void stop();

 private:
  Executor& executor_;
  PeriodicTimer timer_;
  std::function<void()> report_;
};

// Formatting shared by status lines: "42 ms" or "n/a"; "none" or "HighLatency,InvalidMac".
std::string format_latency(const std::optional<std::uint64_t>& latency_ms);
std::string format_faults(const FaultSet& faults);
// Events per second between two counter readings `elapsed` apart (0 when elapsed is 0).
double per_second(std::uint64_t count_now, std::uint64_t count_before, Micros elapsed);

}  // namespace ocp::sim_app
