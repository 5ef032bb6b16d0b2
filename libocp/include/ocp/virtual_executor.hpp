#pragma once
// Deterministic discrete-event executor: a min-heap of (deadline, sequence). Time only moves
// when an event runs. Same inputs → same order of events, byte for byte.
#include <cstddef>
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
  std::uint64_t events_run() const { return events_run_; }
  // Deadline of the next pending event, or nullopt-like SimTime::max() when idle.
  SimTime next_deadline() const;

 private:
  // Tasks live in a slot vector indexed by the low half of the TimerId; the high half is the
  // slot's generation, so a stale id (already run or cancelled) never matches a reused slot.
  // The heap holds only (deadline, sequence, slot, generation): a cancelled entry stays in it
  // until it reaches the front or a compaction, and is recognised by its generation.
  struct Slot {
    Task task;
    std::uint32_t generation = 1;
  };
  struct Entry {
    SimTime deadline;
    std::uint64_t sequence;
    std::uint32_t slot;
    std::uint32_t generation;
  };
  // Heap order: the earliest deadline, then the lowest sequence, is at the front.
  static bool later(const Entry& left, const Entry& right) {
    return left.deadline != right.deadline ? left.deadline > right.deadline
                                           : left.sequence > right.sequence;
  }
  bool is_live(const Entry& entry) const { return slots_[entry.slot].generation == entry.generation; }
  void drop_cancelled_front() const;
  void release_slot(std::uint32_t slot);
  void compact_if_mostly_cancelled();

  SimTime now_;
  std::uint64_t next_sequence_ = 0;
  std::uint64_t events_run_ = 0;
  std::size_t live_count_ = 0;
  mutable std::vector<Entry> heap_;
  std::vector<Slot> slots_;
  std::vector<std::uint32_t> free_slots_;
};

}  // namespace ocp
