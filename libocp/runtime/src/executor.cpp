#include "ocp/executor.hpp"

#include <cassert>

namespace ocp {

PeriodicTimer::PeriodicTimer(Executor& executor, Micros period, TickHandler on_tick)
    : executor_(executor), period_(period), on_tick_(std::move(on_tick)) {
  // A zero period would tick forever at one instant.
  assert(period_.count() > 0);
}

PeriodicTimer::~PeriodicTimer() { stop(); }

void PeriodicTimer::start(SimTime first_deadline) {
  stop();
  next_deadline_ = first_deadline;
  running_ = true;
  arm();
}

void PeriodicTimer::stop() {
  if (timer_ != 0) {
    executor_.cancel(timer_);
    timer_ = 0;
  }
  running_ = false;
}

void PeriodicTimer::arm() {
  timer_ = executor_.call_at(next_deadline_, [this] { fire(); });
}

void PeriodicTimer::fire() {
  timer_ = 0;
  const SimTime deadline = next_deadline_;
  ++ticks_;
  on_tick_(deadline);
  // The handler may have stopped the timer, or stopped and restarted it (which re-armed).
  if (!running_ || timer_ != 0) {
    return;
  }
  next_deadline_ = deadline + period_;
  // Ticks whose deadline already passed are skipped rather than run back to back; a tick
  // due exactly now is on time. Absolute deadlines keep the phase: no drift.
  const SimTime now = executor_.now();
  if (next_deadline_ < now) {
    const auto behind = (now - next_deadline_).count();
    const auto skipped = (behind + period_.count() - 1) / period_.count();
    missed_ticks_ += static_cast<std::uint64_t>(skipped);
    next_deadline_ += period_ * skipped;
  }
  arm();
}

}  // namespace ocp
