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
  const TimerId id = next_id_++;
  // A past deadline runs as soon as possible, after everything already due.
  const SimTime effective = std::max(deadline, now());
  queue_.emplace(QueueKey{effective, id}, std::move(task));
  deadline_by_id_.emplace(id, effective);
  schedule_wake_up();
  return id;
}

void AsioExecutor::cancel(TimerId id) {
  const auto found = deadline_by_id_.find(id);
  if (found == deadline_by_id_.end()) {
    return;
  }
  queue_.erase(QueueKey{found->second, id});
  deadline_by_id_.erase(found);
  if (queue_.empty() && armed_for_) {
    // Nothing left: let the io_context run out of work instead of waiting for the deadline.
    armed_for_.reset();
    ++wait_generation_;
    timer_.cancel();
  }
  // Otherwise the timer stays armed: one wake-up that finds nothing due is cheaper than
  // re-programming the timer on every cancel.
}

void AsioExecutor::schedule_wake_up() {
  if (in_batch_ || queue_.empty()) {
    return;  // a running batch arranges the next wake-up when it ends
  }
  const SimTime earliest = queue_.begin()->first.first;
  if (earliest <= now()) {
    post_batch();
  } else {
    arm_timer(earliest);
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
  // cannot starve the rest of the io_context.
  const SimTime batch_end = now();
  const auto first_not_due = queue_.lower_bound(QueueKey{batch_end + Micros{1}, 0});
  if (first_not_due != queue_.end()) {
    arm_timer(first_not_due->first.first);  // before the tasks: see the header
  }
  // One task at a time: a task may schedule or cancel others, or even destroy this executor.
  const std::shared_ptr<bool> alive = alive_;
  in_batch_ = true;
  while (*alive && !queue_.empty() && queue_.begin()->first.first <= batch_end) {
    auto first = queue_.begin();
    Task task = std::move(first->second);
    deadline_by_id_.erase(first->first.second);
    queue_.erase(first);
    task();
  }
  if (*alive) {
    in_batch_ = false;
    schedule_wake_up();
  }
}

}  // namespace ocp
