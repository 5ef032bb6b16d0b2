#pragma once
// Injected time (ARCHITECTURE.md property 2). One interface, two implementations:
//   VirtualExecutor — a deterministic discrete-event queue ordered by (deadline, sequence);
//                     time jumps from event to event, so an hour runs in about a second.
//   AsioExecutor    — real time on a boost::asio::io_context with steady_timer and absolute
//                     deadlines (see asio_executor.hpp; kept apart so cores never see Asio).
// The same world runs unchanged under either.
#include <cstdint>
#include <functional>

#include "ocp/time.hpp"

namespace ocp {

class Executor {
 public:
  using TimerId = std::uint64_t;
  using Task = std::function<void()>;

  virtual ~Executor() = default;

  // Current time on this executor's timeline (virtual, or real time since construction).
  virtual SimTime now() const = 0;
  // Runs `task` at `deadline` (at once, in order, if the deadline has passed). Tasks with
  // equal deadlines run in the order they were scheduled.
  virtual TimerId call_at(SimTime deadline, Task task) = 0;
  // Cancelling an id that already ran or was cancelled is harmless.
  virtual void cancel(TimerId id) = 0;
  // Runs `task` at `deadline` or up to `slack` later, where that lets it share a wake-up with
  // other work (for a check that usually finds nothing to do: a keep-alive). Virtual time runs
  // it at `deadline` exactly, so nothing deterministic depends on the slack; real time
  // (AsioExecutor) runs it at its first wake-up after the deadline. Linux's timer slack, which
  // timerfd does not apply, done where the tasks are known.
  virtual TimerId call_at_or_later(SimTime deadline, Micros slack, Task task) {
    (void)slack;
    return call_at(deadline, std::move(task));
  }

  TimerId call_after(Micros delay, Task task) { return call_at(now() + delay, std::move(task)); }
  TimerId post(Task task) { return call_at(now(), std::move(task)); }
};

// Calls `on_tick(deadline)` at start, start + period, start + 2·period, … — absolute
// deadlines, so lateness never accumulates into drift. If the executor falls behind by more
// than a period, missed ticks are skipped (counted in `missed_ticks`) instead of bunched.
class PeriodicTimer {
 public:
  using TickHandler = std::function<void(SimTime deadline)>;
  PeriodicTimer(Executor& executor, Micros period, TickHandler on_tick);
  ~PeriodicTimer();
  PeriodicTimer(const PeriodicTimer&) = delete;
  PeriodicTimer& operator=(const PeriodicTimer&) = delete;

  void start(SimTime first_deadline);
  void stop();
  bool running() const { return running_; }
  Micros period() const { return period_; }
  std::uint64_t ticks() const { return ticks_; }
  std::uint64_t missed_ticks() const { return missed_ticks_; }

 private:
  void arm();
  void fire();
  Executor& executor_;
  Micros period_;
  TickHandler on_tick_;
  SimTime next_deadline_{};
  Executor::TimerId timer_ = 0;
  bool running_ = false;
  std::uint64_t ticks_ = 0;
  std::uint64_t missed_ticks_ = 0;
};

}  // namespace ocp
