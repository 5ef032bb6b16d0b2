#include "ocp/asio/executor.hpp"

#include <algorithm>
#include <boost/asio/post.hpp>

namespace ocp {

AsioExecutor::AsioExecutor(boost::asio::io_context& io)
    : io_(io),
      origin_(std::chrono::steady_clock::now()),
      timer_(io),
      alive_(std::make_shared<bool>(true)) {}

AsioExecutor::~AsioExecutor() {
  *alive_ = false;
  timer_.cancel();
}

SimTime AsioExecutor::now() const {
  return std::chrono::duration_cast<SimTime>(std::chrono::steady_clock::now() - origin_);
}

Executor::TimerId AsioExecutor::call_at(SimTime deadline, Task task) {
  return schedule(deadline, Micros{0}, std::move(task));
}

Executor::TimerId AsioExecutor::call_at_or_later(SimTime deadline, Micros slack, Task task) {
  return schedule(deadline, slack, std::move(task));
}

Executor::TimerId AsioExecutor::schedule(SimTime deadline, Micros slack, Task task) {
  // A past deadline runs as soon as possible, after everything already due.
  const SimTime current = now();
  const SimTime effective = std::max(deadline, current);
  const bool lenient = slack.count() > 0 && effective <= SimTime::max() - slack;
  std::uint32_t slot;
  if (free_slots_.empty()) {
    slot = static_cast<std::uint32_t>(slots_.size());
    slots_.emplace_back();
  } else {
    slot = free_slots_.back();
    free_slots_.pop_back();
  }
  Slot& waiting = slots_[slot];
  waiting.task = std::move(task);
  const Entry entry{effective, next_sequence_++, slot, waiting.generation};
  Heap& heap = lenient ? lenient_ : strict_;
  heap.push_back(entry);
  std::push_heap(heap.begin(), heap.end(), runs_later);
  if (lenient) {
    lenient_latest_.push_back(Entry{effective + slack, entry.sequence, slot, entry.generation});
    std::push_heap(lenient_latest_.begin(), lenient_latest_.end(), runs_later);
  }
  ++live_tasks_;
  compact_if_mostly_stale();
  schedule_wake_up(current);
  return (TimerId{entry.generation} << 32) | slot;
}

void AsioExecutor::cancel(TimerId id) {
  const auto slot = static_cast<std::uint32_t>(id & 0xffff'ffffU);
  const auto generation = static_cast<std::uint32_t>(id >> 32);
  if (slot >= slots_.size() || slots_[slot].generation != generation) {
    return;   // already ran or cancelled
  }
  (void)release(slot);   // its heap entries go when they reach the top
  if (live_tasks_ == 0 && armed_for_) {
    // Nothing left: let the io_context run out of work instead of waiting for the deadline.
    armed_for_.reset();
    ++wait_generation_;
    timer_.cancel();
  }
  // Otherwise the timer stays armed: one wake-up that finds nothing due is cheaper than
  // re-programming the timer on every cancel.
}

Executor::Task AsioExecutor::release(std::uint32_t slot) {
  Slot& done = slots_[slot];
  Task task = std::move(done.task);
  done.task = nullptr;
  if (++done.generation == 0) done.generation = 1;   // 0 would make slot 0's id 0, "no timer"
  done.in_batch = false;
  free_slots_.push_back(slot);
  --live_tasks_;
  return task;
}

bool AsioExecutor::is_stale(const Entry& entry) const {
  const Slot& slot = slots_[entry.slot];
  return slot.generation != entry.generation || slot.in_batch;
}

void AsioExecutor::drop_stale_top(Heap& heap) {
  while (!heap.empty() && is_stale(heap.front())) {
    std::pop_heap(heap.begin(), heap.end(), runs_later);
    heap.pop_back();
  }
}

// Entries of cancelled tasks wait to reach the top; a task re-armed far ahead and cancelled
// again and again (a timeout pushed back by every message) would pile them up. Sweeping when
// they outnumber the live ones keeps the heaps within a constant factor of the tasks.
void AsioExecutor::compact_if_mostly_stale() {
  const std::size_t entries = strict_.size() + lenient_.size() + lenient_latest_.size();
  if (entries <= 2 * live_tasks_ + 1024) {
    return;
  }
  for (Heap* heap : {&strict_, &lenient_, &lenient_latest_}) {
    std::erase_if(*heap, [this](const Entry& entry) { return is_stale(entry); });
    std::make_heap(heap->begin(), heap->end(), runs_later);
  }
}

AsioExecutor::Heap* AsioExecutor::front_heap() {
  drop_stale_top(strict_);
  drop_stale_top(lenient_);
  if (strict_.empty()) return lenient_.empty() ? nullptr : &lenient_;
  if (lenient_.empty()) return &strict_;
  return runs_later(strict_.front(), lenient_.front()) ? &lenient_ : &strict_;
}

std::optional<SimTime> AsioExecutor::next_wake() {
  drop_stale_top(strict_);
  drop_stale_top(lenient_latest_);
  std::optional<SimTime> wake;
  if (!strict_.empty()) wake = strict_.front().key;
  if (!lenient_latest_.empty() && (!wake || lenient_latest_.front().key < *wake)) wake = lenient_latest_.front().key;
  return wake;
}

void AsioExecutor::schedule_wake_up(SimTime current) {
  if (in_batch_) {
    return;  // a running batch arranges the next wake-up when it ends
  }
  const Heap* first = front_heap();
  if (first == nullptr) {
    return;
  }
  if (first->front().key <= current) {
    post_batch();
  } else if (const auto wake = next_wake()) {
    arm_timer(*wake);
  }
}

void AsioExecutor::arm_timer(SimTime deadline) {
  if (armed_for_ && *armed_for_ <= deadline) {
    return;  // an earlier (or the same) wake-up is coming; it re-arms for what is left
  }
  armed_for_ = deadline;
  const std::uint64_t generation = ++wait_generation_;
  // expires_at cancels the previous wait; its handler (aborted, or already queued as a
  // success) is recognised as stale by its generation.
  timer_.expires_at(to_steady(deadline));
  timer_.async_wait([this, generation, alive = alive_](const boost::system::error_code& error) {
    if (!*alive || error == boost::asio::error::operation_aborted || generation != wait_generation_) {
      return;
    }
    armed_for_.reset();
    run_due();
  });
}

void AsioExecutor::post_batch() {
  if (batch_posted_) {
    return;
  }
  batch_posted_ = true;
  boost::asio::post(io_, [this, alive = alive_] {
    if (!*alive) {
      return;
    }
    batch_posted_ = false;
    run_due();
  });
}

void AsioExecutor::take_due(SimTime batch_end, std::vector<Entry>& batch) {
  for (Heap* heap = front_heap(); heap != nullptr && heap->front().key <= batch_end; heap = front_heap()) {
    std::pop_heap(heap->begin(), heap->end(), runs_later);
    batch.push_back(heap->back());
    heap->pop_back();
    slots_[batch.back().slot].in_batch = true;
  }
}

void AsioExecutor::run_due() {
  // Only tasks due when the batch began run in it, so a task that keeps re-posting itself
  // cannot starve the rest of the io_context. Tasks with slack whose deadline has passed run
  // here too: this wake-up is theirs for free.
  const SimTime batch_end = now();
  std::vector<Entry> batch;
  batch.swap(batch_buffer_);
  take_due(batch_end, batch);
  if (const auto wake = next_wake()) {
    arm_timer(*wake);  // before the tasks: see the header
  }
  // One task at a time: a task may schedule or cancel others, or even destroy this executor.
  const std::shared_ptr<bool> alive = alive_;
  in_batch_ = true;
  for (const Entry& entry : batch) {
    if (slots_[entry.slot].generation != entry.generation) {
      continue;   // cancelled by an earlier task of this batch
    }
    release(entry.slot)();
    if (!*alive) {
      return;
    }
  }
  batch.clear();
  batch_buffer_.swap(batch);
  in_batch_ = false;
  schedule_wake_up(now());
}

}  // namespace ocp
