#pragma once
// LoopRecorder: everything `ocp_bench loop` reports about one Streamer, taken from its event
// stream only (WireFrame, LatencySample, FaultEvent, ConnectionEvent) — no hooks in the core.
//   echo delay:   control frame out → the first response carrying its pair (WireFrame times:
//                 before the Streamer's write, when its read returned — as the floor measures);
//   responses:    arrival times (rate, largest gap);
//   latency:      LatencySample::latency_ms and tick_lateness per control tick;
//   faults:       every raise and clear, with its time.
// Samples are kept from the first vehicle connection on (before it the Streamer is alone and
// its faults say so); faults are kept from the start and flagged when before the connection.
#include <cstdint>
#include <string>
#include <deque>
#include <utility>
#include <vector>

#include "ocp/event_bus.hpp"

namespace ocp::bench {

struct FaultRecord {
  double at_s = 0;        // seconds since the recorder started
  std::string id;         // "HighLatency"
  bool active = false;    // raised (true) or cleared
  bool before_connect = false;
};

struct TimePoint {
  double at_s = 0;
  double value = 0;
};

class LoopRecorder {
 public:
  LoopRecorder(EventBus& events, SimTime start);

  const std::vector<double>& echo_delays_us() const { return echo_delays_us_; }
  const std::vector<TimePoint>& echo_series_us() const { return echo_series_us_; }
  const std::vector<double>& response_times_s() const { return response_times_s_; }
  const std::vector<double>& latency_ms() const { return latency_ms_; }
  const std::vector<TimePoint>& latency_series_ms() const { return latency_series_ms_; }
  const std::vector<double>& tick_lateness_us() const { return tick_lateness_us_; }
  const std::vector<FaultRecord>& faults() const { return faults_; }
  std::uint64_t control_frames() const { return control_frames_; }
  std::uint64_t connections() const { return connections_; }
  bool connected_once() const { return connections_ > 0; }
  double first_connect_s() const { return first_connect_s_; }

 private:
  void on_event(const Event& event);
  void on_frame(const WireFrame& frame, SimTime at);
  double seconds(SimTime at) const;

  SimTime start_;
  // Pairs sent and not yet echoed, in send order (ack_time grows with every tick).
  std::deque<std::pair<std::uint64_t, SimTime>> sent_at_;
  std::vector<double> echo_delays_us_;
  std::vector<TimePoint> echo_series_us_;
  std::vector<double> response_times_s_;
  std::vector<double> latency_ms_;
  std::vector<TimePoint> latency_series_ms_;
  std::vector<double> tick_lateness_us_;
  std::vector<FaultRecord> faults_;
  std::uint64_t control_frames_ = 0;
  std::uint64_t connections_ = 0;
  double first_connect_s_ = 0;
  EventBus::Subscription subscription_;   // last: unsubscribes before the vectors go
};

}  // namespace ocp::bench
