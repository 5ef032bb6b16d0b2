#pragma once
// FleetRecorder: the fleet figures from a World's event bus (the parent of every Streamer's):
// tick lateness of every control tick, echo delay per vehicle (control frame out → first
// response with its pair), and faults raised, counted per fault. Records only between
// start_recording() and stop_recording(), so connection set-up and warm-up are left out.
#include <array>
#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "ocp/event_bus.hpp"
#include "ocp/faults.hpp"

namespace ocp::bench {

class FleetRecorder {
 public:
  FleetRecorder(EventBus& events, const std::vector<std::string>& vehicles);

  void start_recording() { recording_ = true; }
  void stop_recording() { recording_ = false; }

  std::uint64_t connections() const { return connections_; }
  const std::vector<double>& tick_lateness_us() const { return tick_lateness_us_; }
  const std::vector<double>& echo_delays_us() const { return echo_delays_us_; }
  const std::array<std::uint64_t, fault_count>& faults_raised() const { return faults_raised_; }
  std::uint64_t responses() const { return responses_; }

 private:
  void on_event(const Event& event);
  void on_frame(std::size_t vehicle, const WireFrame& frame, SimTime at);

  std::map<std::string, std::size_t, std::less<>> index_;
  std::vector<std::deque<std::pair<std::uint64_t, SimTime>>> pending_;   // per vehicle, send order
  std::vector<double> tick_lateness_us_;
  std::vector<double> echo_delays_us_;
  std::array<std::uint64_t, fault_count> faults_raised_{};
  std::uint64_t connections_ = 0;
  std::uint64_t responses_ = 0;
  bool recording_ = false;
  EventBus::Subscription subscription_;   // last: unsubscribes first
};

}  // namespace ocp::bench
