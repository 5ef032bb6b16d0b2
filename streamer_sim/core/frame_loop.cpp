#include "frame_loop.hpp"

#include "ocp/invariant.hpp"

namespace ocp::streamer {

FrameLoop::FrameLoop(Executor& executor, double rate_hz, IterationHandler on_iteration)
    : executor_(executor), rate_hz_(rate_hz), on_iteration_(std::move(on_iteration)) {}

FrameLoop::~FrameLoop() { stop(); }

bool FrameLoop::start(SimTime start_time) {
  stop();
  schedule_ = RateSchedule(start_time, rate_hz_);
  if (!schedule_.valid()) return false;
  next_index_ = 0;
  blocked_ = false;
  running_ = true;
  arm();
  return true;
}

void FrameLoop::stop() {
  running_ = false;
  blocked_ = false;
  if (timer_ != 0) executor_.cancel(timer_);
  timer_ = 0;
  OCP_INVARIANT(!running_ && timer_ == 0, "a stopped frame loop holds no timer");
}

void FrameLoop::arm() {
  const SimTime deadline = schedule_.deadline(next_index_);
  timer_ = executor_.call_at(deadline, [this] { on_due(); });
  OCP_INVARIANT(running_ && timer_ != 0, "only a running frame loop arms its timer");
  OCP_INVARIANT(deadline >= schedule_.deadline(0), "a frame is never due before the loop started");
}

void FrameLoop::on_due() {
  timer_ = 0;
  if (!running_) return;
  if (pending_stall_ > Micros{0}) {
    const Micros took = pending_stall_;
    pending_stall_ = Micros{0};
    blocked_ = true;
    timer_ = executor_.call_at(executor_.now() + took, [this, took] { on_stall_done(took); });
    return;
  }
  on_iteration_(Micros{0});
  if (!running_) return;
  const std::uint64_t previous_index = next_index_;
  next_index_ = schedule_.first_index_after(executor_.now(), next_index_ + 1);
  OCP_INVARIANT(next_index_ > previous_index, "frames are indexed forward: a late loop skips, never repeats");
  arm();
}

void FrameLoop::on_stall_done(Micros took) {
  timer_ = 0;
  blocked_ = false;
  if (!running_) return;
  on_iteration_(took);
  if (!running_) return;
  next_index_ = schedule_.first_index_after(executor_.now(), next_index_ + 1);
  arm();
}

}  // namespace ocp::streamer
