#pragma once
// Deterministic discrete-event executor ordered by (deadline, scheduling order). Time only
// moves when an event runs. Same inputs → same order of events, byte for byte.
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "ocp/executor.hpp"

namespace ocp {

class VirtualExecutor final : public Executor {
 public:
  explicit VirtualExecutor(SimTime start = SimTime{0});

  SimTime now() const override { return now_; }
  TimerId call_at(SimTime deadline, Task task) override;
  void cancel(TimerId id) override;

  // Runs the next event (advancing time to its deadline). False when nothing is pending.
  bool step();
  // Runs every event with deadline <= end, then sets now() to `end`.
  void run_until(SimTime end);
  void run_for(Micros duration) { run_until(now_ + duration); }
  // Runs until idle or `max_steps` events ran; returns the number of events run.
  std::size_t drive_bounded(std::size_t max_steps);

  std::size_t pending() const;

  // The most events pending at once. One more is a runaway schedule (a timer rescheduling
  // itself more than once per run, a link with a huge rate or delay): call_at throws
  // std::length_error naming the limit, before memory runs out. The default holds a fleet of
  // 10 000 vehicles with long links many times over.
  static constexpr std::size_t default_pending_limit = std::size_t{1} << 24;
  void set_pending_limit(std::size_t limit) { pending_limit_ = limit; }
  std::uint64_t events_run() const { return events_run_; }
  // Deadline of the next pending event, or nullopt-like SimTime::max() when idle.
  SimTime next_deadline() const;

 private:
  // The invariants every handler of the queue leaves true (virtual_executor.cpp).
  void check_counts() const;
  std::size_t pending_limit_ = default_pending_limit;
  // Tasks live in a slot vector indexed by the low half of the TimerId; the high half is the
  // slot's generation, so a stale id (already run or cancelled) never matches a reused slot.
  struct Slot {
    Task task;
    std::uint32_t generation = 1;
  };
  // A queued event: its slot and the generation it was scheduled with. A cancelled event
  // stays queued until it reaches the front or a compaction, and is recognised by its
  // generation.
  struct Item {
    std::uint32_t slot;
    std::uint32_t generation;
  };
  // Why buckets and not one heap of events: a world's events share few deadlines (every
  // vehicle ticks on the same 10 ms grid, and a zero-delay pipe or link delivers at `now`), so
  // a heap of 10 000 vehicles' events costs ~17 cache-missing levels per push and pop. Here
  // the heap holds one bucket per distinct deadline, and each bucket is a FIFO in scheduling
  // order — exactly the (deadline, sequence) order, at O(1) per event within a deadline.
  struct Bucket {
    SimTime deadline{};
    std::vector<Item> items;  // FIFO: items before `head` have run or were skipped
    std::size_t head = 0;
  };
  static constexpr std::uint32_t no_bucket = UINT32_MAX;

  bool is_live(const Item& item) const { return slots_[item.slot].generation == item.generation; }
  std::uint32_t bucket_for(SimTime deadline);
  void release_front_bucket() const;
  void drop_cancelled_front() const;
  void release_slot(std::uint32_t slot);
  void compact_if_mostly_cancelled();
  void push_bucket(std::uint32_t bucket) const;
  void pop_bucket() const;

  SimTime now_;
  std::uint64_t events_run_ = 0;
  std::size_t live_count_ = 0;
  mutable std::size_t queued_items_ = 0;   // live and cancelled items still queued
  mutable std::vector<Bucket> buckets_;    // storage; indices are stable
  mutable std::vector<std::uint32_t> free_buckets_;
  mutable std::vector<std::uint32_t> bucket_heap_;  // min-heap of bucket indices by deadline
  mutable std::unordered_map<SimTime::rep, std::uint32_t> bucket_by_deadline_;
  // The bucket the last call_at used: consecutive calls mostly share a deadline.
  mutable std::uint32_t last_bucket_ = no_bucket;
  std::vector<Slot> slots_;
  std::vector<std::uint32_t> free_slots_;
};

}  // namespace ocp
