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
  const TimerId id = next_id_++;
  // A past deadline runs as soon as possible, after everything already due.
  const SimTime effective = std::max(deadline, now());
  const bool lenient = slack.count() > 0 && effective <= SimTime::max() - slack;
  const SimTime latest = lenient ? effective + slack : effective;
  (lenient ? lenient_ : strict_).emplace(QueueKey{effective, id}, std::move(task));
  if (lenient) lenient_latest_.emplace(latest, id);
  pending_.emplace(id, Pending{effective, latest});
  schedule_wake_up();
  return id;
}

void AsioExecutor::cancel(TimerId id) {
  const auto found = pending_.find(id);
  if (found == pending_.end()) {
    return;
  }
  const Pending pending = found->second;
  pending_.erase(found);
  if (pending.latest == pending.deadline) {
    strict_.erase(QueueKey{pending.deadline, id});
  } else {
    lenient_.erase(QueueKey{pending.deadline, id});
    lenient_latest_.erase({pending.latest, id});
  }
  if (front_queue() == nullptr && armed_for_) {
    // Nothing left: let the io_context run out of work instead of waiting for the deadline.
    armed_for_.reset();
    ++wait_generation_;
    timer_.cancel();
  }
  // Otherwise the timer stays armed: one wake-up that finds nothing due is cheaper than
  // re-programming the timer on every cancel.
}

AsioExecutor::Queue* AsioExecutor::front_queue() {
  if (strict_.empty()) return lenient_.empty() ? nullptr : &lenient_;
  if (lenient_.empty()) return &strict_;
  return lenient_.begin()->first < strict_.begin()->first ? &lenient_ : &strict_;
}

std::optional<SimTime> AsioExecutor::next_wake_after(SimTime after) const {
  std::optional<SimTime> wake;
  if (const auto strict = strict_.lower_bound(QueueKey{after + Micros{1}, 0}); strict != strict_.end()) {
    wake = strict->first.first;
  }
  // The earliest latest instant of a task not yet due; the due ones skipped here run in the
  // batch that asks, so each is skipped at most once.
  for (const auto& [latest, id] : lenient_latest_) {
    if (wake && latest >= *wake) break;
    if (pending_.at(id).deadline > after) {
      wake = latest;
      break;
    }
  }
  return wake;
}

void AsioExecutor::schedule_wake_up() {
  if (in_batch_) {
    return;  // a running batch arranges the next wake-up when it ends
  }
  const Queue* first = front_queue();
  if (first == nullptr) {
    return;
  }
  const SimTime current = now();
  if (first->begin()->first.first <= current) {
    post_batch();
  } else if (const auto wake = next_wake_after(current)) {
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

void AsioExecutor::run_due() {
  // Only tasks due when the batch began run in it, so a task that keeps re-posting itself
  // cannot starve the rest of the io_context. Tasks with slack whose deadline has passed run
  // here too: this wake-up is theirs for free.
  const SimTime batch_end = now();
  if (const auto wake = next_wake_after(batch_end)) {
    arm_timer(*wake);  // before the tasks: see the header
  }
  // One task at a time: a task may schedule or cancel others, or even destroy this executor.
  const std::shared_ptr<bool> alive = alive_;
  in_batch_ = true;
  while (*alive) {
    Queue* queue = front_queue();
    if (queue == nullptr || queue->begin()->first.first > batch_end) break;
    const auto first = queue->begin();
    const TimerId id = first->first.second;
    Task task = std::move(first->second);
    queue->erase(first);
    if (const auto pending = pending_.find(id); pending != pending_.end()) {
      if (pending->second.latest != pending->second.deadline) lenient_latest_.erase({pending->second.latest, id});
      pending_.erase(pending);
    }
    task();
  }
  if (*alive) {
    in_batch_ = false;
    schedule_wake_up();
  }
}

}  // namespace ocp
