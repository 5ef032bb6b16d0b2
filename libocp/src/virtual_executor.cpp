#include "ocp/virtual_executor.hpp"

#include <algorithm>

namespace ocp {
namespace {

constexpr int generation_shift = 32;

Executor::TimerId make_id(std::uint32_t slot, std::uint32_t generation) {
  return (static_cast<Executor::TimerId>(generation) << generation_shift) | slot;
}

}  // namespace

VirtualExecutor::VirtualExecutor(SimTime start) : now_(start) {}

Executor::TimerId VirtualExecutor::call_at(SimTime deadline, Task task) {
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
  heap_.push_back(Entry{effective, next_sequence_++, slot, entry_slot.generation});
  std::push_heap(heap_.begin(), heap_.end(), later);
  ++live_count_;
  // Generations start at 1, so no id is ever 0 (0 means "no timer" to callers).
  return make_id(slot, entry_slot.generation);
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
}

void VirtualExecutor::release_slot(std::uint32_t slot) {
  Slot& released = slots_[slot];
  // Skip 0 on wrap-around so an id is never 0.
  released.generation = released.generation == UINT32_MAX ? 1 : released.generation + 1;
  free_slots_.push_back(slot);
}

void VirtualExecutor::drop_cancelled_front() const {
  while (!heap_.empty() && !is_live(heap_.front())) {
    std::pop_heap(heap_.begin(), heap_.end(), later);
    heap_.pop_back();
  }
}

void VirtualExecutor::compact_if_mostly_cancelled() {
  // Cancelled entries wait in the heap until they surface. A caller that keeps re-arming a
  // far-off watchdog would let them pile up, so rebuild once they are the clear majority.
  constexpr std::size_t minimum_heap_for_compaction = 1024;
  if (heap_.size() < minimum_heap_for_compaction || heap_.size() < 4 * live_count_) {
    return;
  }
  std::erase_if(heap_, [this](const Entry& entry) { return !is_live(entry); });
  std::make_heap(heap_.begin(), heap_.end(), later);
}

bool VirtualExecutor::step() {
  drop_cancelled_front();
  if (heap_.empty()) {
    return false;
  }
  const Entry entry = heap_.front();
  std::pop_heap(heap_.begin(), heap_.end(), later);
  heap_.pop_back();
  now_ = entry.deadline;
  // Move the task out and free its slot before running it: the task may schedule or cancel.
  Task task = std::move(slots_[entry.slot].task);
  slots_[entry.slot].task = nullptr;
  release_slot(entry.slot);
  --live_count_;
  ++events_run_;
  task();
  return true;
}

void VirtualExecutor::run_until(SimTime end) {
  while (true) {
    drop_cancelled_front();
    if (heap_.empty() || heap_.front().deadline > end) {
      break;
    }
    step();
  }
  now_ = std::max(now_, end);
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
  return heap_.empty() ? SimTime::max() : heap_.front().deadline;
}

}  // namespace ocp
