#pragma once
// The Streamer frame loop (SPEC §6 StreamerSlow, §8): one iteration per frame at
// `rate_hz` on absolute deadlines. Each completed iteration reports how long it took.
//
// A stall injected with inject_stall(d) blocks the next iteration: it starts at its deadline,
// completes d later (nothing else of the loop runs meanwhile), and reports d. The loop then
// resumes at the first deadline strictly after the completion; missed deadlines are skipped.
// A normal iteration takes no virtual time and reports 0.
#include <functional>

#include "ocp/executor.hpp"
#include "rate_schedule.hpp"

namespace ocp::streamer {

class FrameLoop {
 public:
  using IterationHandler = std::function<void(Micros took)>;

  FrameLoop(Executor& executor, double rate_hz, IterationHandler on_iteration);
  ~FrameLoop();
  FrameLoop(const FrameLoop&) = delete;
  FrameLoop& operator=(const FrameLoop&) = delete;

  // False when the rate is not a positive number (the loop then never runs).
  bool start(SimTime start_time);
  void stop();
  void inject_stall(Micros duration) { pending_stall_ = duration; }
  bool blocked() const { return blocked_; }

 private:
  void arm();
  void on_due();
  void on_stall_done(Micros took);

  Executor& executor_;
  double rate_hz_;
  IterationHandler on_iteration_;
  RateSchedule schedule_{SimTime{0}, 0.0};
  std::uint64_t next_index_ = 0;
  Micros pending_stall_{0};
  bool blocked_ = false;
  bool running_ = false;
  Executor::TimerId timer_ = 0;
};

}  // namespace ocp::streamer
