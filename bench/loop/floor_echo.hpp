#pragma once
// FloorEcho: the machine's floor for the echo delay, measured beside the client under test:
// two threads, plain blocking TCP_NODELAY sockets on loopback, a frame of a control frame's
// size sent every 10 ms on absolute deadlines and echoed at once. No Streamer, no client, no
// reactor — only the kernel's loopback and two thread wake-ups.
#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

namespace ocp::bench {

class FloorEcho {
 public:
  // The first frame goes at `first_send`, the next ones every 10 ms after it. `ocp_bench loop`
  // puts that grid between the Streamer's ticks, so the floor never shares a moment with the
  // loop it is compared with (see loop_command.cpp, "phases").
  explicit FloorEcho(std::chrono::steady_clock::time_point first_send =
                         std::chrono::steady_clock::now() + std::chrono::milliseconds(10));
  ~FloorEcho() { stop(); }
  FloorEcho(const FloorEcho&) = delete;
  FloorEcho& operator=(const FloorEcho&) = delete;

  void stop();   // joins; round_trips_us() is complete afterwards
  const std::vector<double>& round_trips_us() const { return round_trips_us_; }

 private:
  std::atomic<bool> stop_{false};
  std::vector<double> round_trips_us_;
  std::thread thread_;
};

}  // namespace ocp::bench
