#pragma once
// FleetRecorder: the fleet figures from the event stream: tick lateness of every control
// tick, echo delay per vehicle (control frame out → first response with its pair), and faults
// raised, counted per fault. Records only between start_recording() and stop_recording(), so
// connection set-up and warm-up are left out.
//
// Either one bus that sees every Streamer (a World's, single-threaded), or the Streamers' own
// buses when they run on several threads: then one recorder per thread, subscribed to that
// thread's Streamers, and merged once the threads have stopped. connections() and the
// recording switch may be used from another thread.
#include <array>
#include <atomic>
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
  // One bus carrying every vehicle's events (named as in `vehicles`).
  FleetRecorder(EventBus& events, const std::vector<std::string>& vehicles);
  // One bus per vehicle: buses[i] carries vehicle i's Streamer events only.
  explicit FleetRecorder(const std::vector<EventBus*>& buses);

  void start_recording() { recording_ = true; }
  void stop_recording() { recording_ = false; }
  // Adds another recorder's figures (both idle).
  void merge(const FleetRecorder& other);

  std::uint64_t connections() const { return connections_; }
  const std::vector<double>& tick_lateness_us() const { return tick_lateness_us_; }
  const std::vector<double>& echo_delays_us() const { return echo_delays_us_; }
  const std::array<std::uint64_t, fault_count>& faults_raised() const { return faults_raised_; }
  std::uint64_t responses() const { return responses_; }
  // Mean bytes on the wire (length prefix + payload) of a control frame out and of a response
  // in; 0 when none was recorded. The kernel floor (kernel_floor.hpp) sends frames of these sizes.
  double mean_control_bytes() const { return mean(control_bytes_, control_frames_); }
  double mean_response_bytes() const { return mean(response_bytes_, responses_); }
  // The first control message and vehicle response payloads recorded (the codec floor's
  // samples, codec_floor.hpp); empty if none.
  const std::string& sample_control() const { return sample_control_; }
  const std::string& sample_response() const { return sample_response_; }

 private:
  static double mean(std::uint64_t total, std::uint64_t count) {
    return count ? static_cast<double>(total) / static_cast<double>(count) : 0.0;
  }
  void on_event(const Event& event, std::size_t vehicle);
  void on_frame(std::size_t vehicle, const WireFrame& frame, SimTime at);

  static constexpr std::size_t unknown_vehicle = ~std::size_t{0};
  std::map<std::string, std::size_t, std::less<>> index_;   // one-bus form: name → vehicle
  std::vector<std::deque<std::pair<std::uint64_t, SimTime>>> pending_;   // per vehicle, send order
  std::vector<double> tick_lateness_us_;
  std::vector<double> echo_delays_us_;
  std::array<std::uint64_t, fault_count> faults_raised_{};
  std::atomic<std::uint64_t> connections_ = 0;
  std::uint64_t responses_ = 0;
  std::uint64_t control_frames_ = 0, control_bytes_ = 0, response_bytes_ = 0;
  std::string sample_control_, sample_response_;
  std::atomic<bool> recording_ = false;
  std::vector<EventBus::Subscription> subscriptions_;   // last: unsubscribe first
};

}  // namespace ocp::bench
