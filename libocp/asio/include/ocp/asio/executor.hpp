#pragma once
// Real-time executor on a boost::asio::io_context: now() is steady_clock time since
// construction; call_at queues the task at its absolute deadline and one steady_timer is
// armed for the earliest one.
//
// Why the OS timer is touched as little as possible: on a virtual machine, re-programming a
// timer costs 10–60 µs (a VM exit to re-program the host's timer; worse for one already
// expired). Done between a task's socket write and this thread going back to sleep, that cost
// sits inside the peer's round trip when both threads share a core (the kernel wakes the peer
// on the writer's core and it waits there). So:
//   * a batch arms the timer for the next deadline *before* running its tasks, and re-arms
//     afterwards only if a task scheduled something earlier;
//   * a task that is already due (post(), a zero delay, a deadline that passed during the
//     batch) never goes through the timer: the next batch is posted to the io_context instead.
#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <unordered_map>
#include <utility>

#include "ocp/executor.hpp"

namespace ocp {

class AsioExecutor final : public Executor {
 public:
  explicit AsioExecutor(boost::asio::io_context& io);
  ~AsioExecutor() override;

  SimTime now() const override;
  TimerId call_at(SimTime deadline, Task task) override;
  // Runs at the first wake-up of this executor at or after `deadline` (a timer of another task,
  // a post), and no later than deadline + slack: with slack ≥ the gap between the thread's
  // other timers it never costs a wake-up of its own.
  TimerId call_at_or_later(SimTime deadline, Micros slack, Task task) override;
  void cancel(TimerId id) override;

  boost::asio::io_context& io() { return io_; }
  // Converts a SimTime on this executor's timeline to a steady_clock time point.
  std::chrono::steady_clock::time_point to_steady(SimTime t) const { return origin_ + t; }

 private:
  // One steady_timer armed for the earliest deadline of an ordered queue, rather than one
  // timer per task: Asio does not promise FIFO order for equal expiry times, we do.
  // Key = (deadline, id); ids grow monotonically, so they double as the scheduling order.
  // Tasks with slack wait in a queue of their own, and their latest instants in a third: the
  // timer is armed for the earliest strict deadline or latest instant, whichever comes first;
  // tasks run in (deadline, id) order across both queues.
  using QueueKey = std::pair<SimTime, TimerId>;
  using Queue = std::map<QueueKey, Task>;
  struct Pending {
    SimTime deadline;
    SimTime latest;   // == deadline: a strict task
  };
  TimerId schedule(SimTime deadline, Micros slack, Task task);
  // The queue whose first task runs next, or nullptr when nothing is queued.
  Queue* front_queue();
  // When the executor must wake at the latest for the tasks not due at `after`.
  std::optional<SimTime> next_wake_after(SimTime after) const;
  // Makes sure the earliest task will run: posts a batch if it is due, else arms the timer.
  void schedule_wake_up();
  void arm_timer(SimTime deadline);
  void post_batch();
  void run_due();

  boost::asio::io_context& io_;
  std::chrono::steady_clock::time_point origin_;
  TimerId next_id_ = 1;
  Queue strict_;
  Queue lenient_;
  std::set<std::pair<SimTime, TimerId>> lenient_latest_;
  std::unordered_map<TimerId, Pending> pending_;
  boost::asio::steady_timer timer_;
  std::optional<SimTime> armed_for_;
  std::uint64_t wait_generation_ = 0;
  bool batch_posted_ = false;
  bool in_batch_ = false;
  // Shared with pending handlers so they do nothing once this executor is gone.
  std::shared_ptr<bool> alive_;
};

}  // namespace ocp
