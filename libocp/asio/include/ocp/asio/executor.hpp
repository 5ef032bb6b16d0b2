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
#include <memory>
#include <optional>
#include <utility>
#include <vector>

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
  // One steady_timer armed for the earliest deadline of our own queues, rather than one timer
  // per task: Asio does not promise FIFO order for equal expiry times, we do. Tasks run in
  // (deadline, scheduling sequence) order across both kinds.
  //
  // Why heaps over a slot vector and not ordered maps: a fleet's executor schedules and runs
  // tens of thousands of tasks a second (link deliveries, ticks, keep-alive checks), and a map
  // node (plus its index entries) was three allocations and a rebalance per task (~5 % of a
  // loopback fleet's CPU; docs/benchmarks.md, issue #41). Here a task waits in a reusable slot;
  // a TimerId is the slot's index in the low half and its generation in the high half, so an
  // id that already ran or was cancelled never matches the slot's next task. A cancelled task's
  // heap entries stay queued until they reach the top, recognised by their generation.
  struct Slot {
    Task task;
    std::uint32_t generation = 1;
    bool in_batch = false;   // taken out of the heaps by the running batch, not run yet
  };
  // A heap entry: `key` is the task's deadline (strict_, lenient_) or its latest instant
  // (lenient_latest_).
  struct Entry {
    SimTime key;
    std::uint64_t sequence;
    std::uint32_t slot;
    std::uint32_t generation;
  };
  using Heap = std::vector<Entry>;
  TimerId schedule(SimTime deadline, Micros slack, Task task);
  // Min-heap order for the std heap algorithms: what runs (or wakes) first is on top.
  static bool runs_later(const Entry& a, const Entry& b) {
    return a.key != b.key ? a.key > b.key : a.sequence > b.sequence;
  }
  // The entry's task ran, was cancelled, or is in the running batch.
  bool is_stale(const Entry& entry) const;
  void drop_stale_top(Heap& heap);
  void compact_if_mostly_stale();
  // The heap whose top task runs next, or nullptr when nothing is queued.
  Heap* front_heap();
  // When the executor must wake at the latest for the tasks still in the heaps.
  std::optional<SimTime> next_wake();
  // Makes sure the earliest task will run: posts a batch if it is due, else arms the timer.
  void schedule_wake_up(SimTime current);
  void arm_timer(SimTime deadline);
  void post_batch();
  void run_due();
  // Moves the entries due at `batch_end` out of the heaps into `batch`, in running order.
  void take_due(SimTime batch_end, std::vector<Entry>& batch);
  // Ends a task's life (run or cancelled): its slot is free for the next one.
  Task release(std::uint32_t slot);

  boost::asio::io_context& io_;
  std::chrono::steady_clock::time_point origin_;
  std::uint64_t next_sequence_ = 0;
  std::vector<Slot> slots_;
  std::vector<std::uint32_t> free_slots_;
  std::size_t live_tasks_ = 0;
  Heap strict_;
  Heap lenient_;
  Heap lenient_latest_;
  std::vector<Entry> batch_buffer_;   // capacity reused from batch to batch
  boost::asio::steady_timer timer_;
  std::optional<SimTime> armed_for_;
  std::uint64_t wait_generation_ = 0;
  bool batch_posted_ = false;
  bool in_batch_ = false;
  // Shared with pending handlers so they do nothing once this executor is gone.
  std::shared_ptr<bool> alive_;
};

}  // namespace ocp
