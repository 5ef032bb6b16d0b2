#include "loop_result.hpp"

#include <algorithm>

namespace ocp::bench {

std::size_t LoopResult::faults_after_connect() const {
  return static_cast<std::size_t>(std::count_if(client.faults.begin(), client.faults.end(),
                                                [](const FaultRecord& fault) { return fault.active && !fault.before_connect; }));
}

ClientFigures figures_from(const std::string& name, const LoopRecorder& recorder, double duration_s) {
  ClientFigures figures;
  figures.name = name;
  figures.echo_us = summarize(recorder.echo_delays_us());
  figures.control_frames = recorder.control_frames();
  figures.response_times_s = recorder.response_times_s();
  figures.responses = figures.response_times_s.size();
  // Rate over the time the client was connected, not over the wait for it.
  const double connected_s = duration_s - recorder.first_connect_s();
  figures.responses_per_s = connected_s > 0 ? static_cast<double>(figures.responses) / connected_s : 0.0;
  const auto& times = figures.response_times_s;
  for (std::size_t index = 1; index < times.size(); ++index) {
    figures.max_response_gap_ms = std::max(figures.max_response_gap_ms, 1e3 * (times[index] - times[index - 1]));
  }
  figures.latency_ms = summarize(recorder.latency_ms());
  figures.tick_lateness_us = summarize(recorder.tick_lateness_us());
  figures.connections = recorder.connections();
  figures.faults = recorder.faults();
  figures.echo_delays_us = recorder.echo_delays_us();
  figures.echo_series_us = recorder.echo_series_us();
  figures.latency_series_ms = recorder.latency_series_ms();
  return figures;
}

}  // namespace ocp::bench
