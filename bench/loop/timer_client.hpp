#pragma once
// TimerClient: the "naive client" reference for `ocp_bench loop --compare`. It connects to a
// Streamer, decodes control messages only to remember the newest pair, and answers on its own
// 10 ms timer with that pair — never on arrival. Its echo delay is what a client whose
// response is paced by its own control loop gets: 0–10 ms, spread evenly over a 10 s run (the
// timer runs 10 µs slow, see tick()). A client under test near the machine floor and far below
// this one echoes at once. Own thread and io_context.
#include <atomic>
#include <cstdint>
#include <thread>

namespace ocp::bench {

class TimerClient {
 public:
  explicit TimerClient(std::uint16_t port);
  ~TimerClient() { stop(); }
  TimerClient(const TimerClient&) = delete;
  TimerClient& operator=(const TimerClient&) = delete;
  void stop();

 private:
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace ocp::bench
