#include "ocp/virtual_executor.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "ocp/invariant.hpp"

namespace ocp {
namespace {

constexpr int generation_shift = 32;

Executor::TimerId make_id(std::uint32_t slot, std::uint32_t generation) {
  return (static_cast<Executor::TimerId>(generation) << generation_shift) | slot;
}

}  // namespace

VirtualExecutor::VirtualExecutor(SimTime start) : now_(start) {}

Executor::TimerId VirtualExecutor::call_at(SimTime deadline, Task task) {
  if (live_count_ >= pending_limit_) {
    throw std::length_error("virtual executor: " + std::to_string(pending_limit_) +
                            " events pending at once (the limit): a runaway schedule, at " + std::to_string(now_.count()) +
                            " us of virtual time");
  }
  std::uint32_t slot;
  if (!free_slots_.empty()) {
    slot = free_slots_.back();
    free_slots_.pop_back();
  } else {
    slot = static_cast<std::uint32_t>(slots_.size());
    slots_.emplace_back();
  }
  Slot& entry_slot = slots_[slot];
  entry_slot.task = std::move(task);
  // A deadline in the past runs at once: time never moves backwards.
  const SimTime effective = std::max(deadline, now_);
  buckets_[bucket_for(effective)].items.push_back(Item{slot, entry_slot.generation});
  ++queued_items_;
  ++live_count_;
  check_counts();
  OCP_INVARIANT(live_count_ <= pending_limit_, "call_at never takes the queue beyond its pending limit");
  OCP_INVARIANT(entry_slot.generation != 0, "timer generations start at 1, so no id is ever 0");
  // Generations start at 1, so no id is ever 0 (0 means "no timer" to callers).
  return make_id(slot, entry_slot.generation);
}

std::uint32_t VirtualExecutor::bucket_for(SimTime deadline) {
  if (last_bucket_ != no_bucket && buckets_[last_bucket_].deadline == deadline) {
    return last_bucket_;
  }
  const auto [found, inserted] = bucket_by_deadline_.try_emplace(deadline.count(), no_bucket);
  if (inserted) {
    std::uint32_t bucket;
    if (!free_buckets_.empty()) {
      bucket = free_buckets_.back();
      free_buckets_.pop_back();
    } else {
      bucket = static_cast<std::uint32_t>(buckets_.size());
      buckets_.emplace_back();
    }
    buckets_[bucket].deadline = deadline;
    found->second = bucket;
    push_bucket(bucket);
  }
  last_bucket_ = found->second;
  return last_bucket_;
}

void VirtualExecutor::push_bucket(std::uint32_t bucket) const {
  bucket_heap_.push_back(bucket);
  std::push_heap(bucket_heap_.begin(), bucket_heap_.end(), [this](std::uint32_t left, std::uint32_t right) {
    return buckets_[left].deadline > buckets_[right].deadline;
  });
}

void VirtualExecutor::pop_bucket() const {
  std::pop_heap(bucket_heap_.begin(), bucket_heap_.end(), [this](std::uint32_t left, std::uint32_t right) {
    return buckets_[left].deadline > buckets_[right].deadline;
  });
  bucket_heap_.pop_back();
}

void VirtualExecutor::release_front_bucket() const {
  const std::uint32_t bucket = bucket_heap_.front();
  pop_bucket();
  Bucket& released = buckets_[bucket];
  bucket_by_deadline_.erase(released.deadline.count());
  queued_items_ -= released.items.size() - released.head;
  released.items.clear();  // keeps its capacity for the next deadline
  released.head = 0;
  free_buckets_.push_back(bucket);
  if (last_bucket_ == bucket) last_bucket_ = no_bucket;
}

void VirtualExecutor::cancel(TimerId id) {
  const auto slot = static_cast<std::uint32_t>(id & 0xffffffffu);
  const auto generation = static_cast<std::uint32_t>(id >> generation_shift);
  if (slot >= slots_.size() || slots_[slot].generation != generation) {
    return;  // already ran, already cancelled, or never existed
  }
  slots_[slot].task = nullptr;
  release_slot(slot);
  --live_count_;
  compact_if_mostly_cancelled();
  check_counts();
}

// What every handler of the queue leaves true: each slot is free or holds one live task, each
// live task has one queued item, and each bucket is both in the heap and in the index. Deep:
// they run twice per event, the hottest path of a virtual run (world_bench OneHour measured
// 1.10× with them on in release); time never going back stays on everywhere (step()).
void VirtualExecutor::check_counts() const {
  OCP_INVARIANT_DEEP(free_slots_.size() + live_count_ == slots_.size(), "each timer slot is free or holds one live task");
  OCP_INVARIANT_DEEP(queued_items_ >= live_count_, "each live task has its item in a bucket");
  OCP_INVARIANT_DEEP(bucket_by_deadline_.size() == bucket_heap_.size(), "each bucket is in the heap and the deadline index");
  OCP_INVARIANT_DEEP(bucket_heap_.empty() || buckets_[bucket_heap_.front()].deadline >= now_,
                "the queue is ordered: its earliest deadline is never before now");
  OCP_INVARIANT_DEEP(std::is_heap(bucket_heap_.begin(), bucket_heap_.end(),
                                  [this](std::uint32_t left, std::uint32_t right) {
                                    return buckets_[left].deadline > buckets_[right].deadline;
                                  }),
                     "the buckets form a heap on their deadlines");
}

void VirtualExecutor::release_slot(std::uint32_t slot) {
  Slot& released = slots_[slot];
  // Skip 0 on wrap-around so an id is never 0.
  released.generation = released.generation == UINT32_MAX ? 1 : released.generation + 1;
  free_slots_.push_back(slot);
}

void VirtualExecutor::drop_cancelled_front() const {
  while (!bucket_heap_.empty()) {
    Bucket& front = buckets_[bucket_heap_.front()];
    while (front.head < front.items.size() && !is_live(front.items[front.head])) {
      ++front.head;
      --queued_items_;
    }
    if (front.head < front.items.size()) return;
    release_front_bucket();
  }
}

void VirtualExecutor::compact_if_mostly_cancelled() {
  // Cancelled items wait in their bucket until they surface. A caller that keeps re-arming a
  // far-off watchdog would let them pile up, so sweep once they are the clear majority.
  constexpr std::size_t minimum_items_for_compaction = 1024;
  if (queued_items_ < minimum_items_for_compaction || queued_items_ < 4 * live_count_) {
    return;
  }
  queued_items_ = 0;
  for (const std::uint32_t bucket : bucket_heap_) {
    Bucket& swept = buckets_[bucket];
    const auto first = swept.items.begin() + static_cast<std::ptrdiff_t>(swept.head);
    swept.items.erase(std::remove_if(first, swept.items.end(), [this](const Item& item) { return !is_live(item); }),
                      swept.items.end());
    swept.items.erase(swept.items.begin(), first);
    swept.head = 0;
    queued_items_ += swept.items.size();
  }
  // Buckets left empty are released as they reach the front (drop_cancelled_front).
}

bool VirtualExecutor::step() {
  drop_cancelled_front();
  if (bucket_heap_.empty()) {
    return false;
  }
  Bucket& front = buckets_[bucket_heap_.front()];
  const Item item = front.items[front.head++];
  --queued_items_;
  OCP_INVARIANT(front.deadline >= now_, "virtual time never goes back: call_at clamps past deadlines to now");
  now_ = front.deadline;
  if (front.head == front.items.size()) {
    release_front_bucket();
  } else if (front.head >= 4096 && 2 * front.head >= front.items.size()) {
    // A deadline that keeps receiving zero-delay events while it runs: drop the run part.
    front.items.erase(front.items.begin(), front.items.begin() + static_cast<std::ptrdiff_t>(front.head));
    front.head = 0;
  }
  // Move the task out and free its slot before running it: the task may schedule or cancel.
  Task task = std::move(slots_[item.slot].task);
  slots_[item.slot].task = nullptr;
  release_slot(item.slot);
  --live_count_;
  ++events_run_;
  check_counts();
  const SimTime ran_at = now_;
  task();
  OCP_INVARIANT(now_ >= ran_at, "virtual time never goes back, across a task either");
  return true;
}

void VirtualExecutor::run_until(SimTime end) {
  while (true) {
    drop_cancelled_front();
    if (bucket_heap_.empty() || buckets_[bucket_heap_.front()].deadline > end) {
      break;
    }
    step();
  }
  now_ = std::max(now_, end);
  OCP_INVARIANT(now_ >= end, "run_until leaves the clock at its end or later");
  OCP_INVARIANT(bucket_heap_.empty() || buckets_[bucket_heap_.front()].deadline > end,
                "run_until leaves no event due by its end");
}

std::size_t VirtualExecutor::drive_bounded(std::size_t max_steps) {
  std::size_t steps = 0;
  while (steps < max_steps && step()) {
    ++steps;
  }
  return steps;
}

std::size_t VirtualExecutor::pending() const { return live_count_; }

SimTime VirtualExecutor::next_deadline() const {
  drop_cancelled_front();
  return bucket_heap_.empty() ? SimTime::max() : buckets_[bucket_heap_.front()].deadline;
}

}  // namespace ocp
