#pragma once
// Deterministic discrete-event executor: a min-heap of (deadline, sequence). Time only moves
// when an event runs. Same inputs → same order of events, byte for byte.
#include <cstddef>
#include <queue>
#include <unordered_set>
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
  struct Entry {
    SimTime deadline;
    std::uint64_t sequence;
    TimerId id;
    // Later deadline (then later sequence) has lower priority.
    bool operator<(const Entry& other) const {
      return deadline != other.deadline ? deadline > other.deadline : sequence > other.sequence;
    }
  };
  void drop_cancelled_front();

  SimTime now_;
  std::uint64_t next_sequence_ = 0;
  TimerId next_id_ = 1;
  std::uint64_t events_run_ = 0;
  std::priority_queue<Entry> queue_;
  std::vector<Task> tasks_by_slot_;        // implementation detail; see .cpp
  std::unordered_set<TimerId> cancelled_;
};

}  // namespace ocp
