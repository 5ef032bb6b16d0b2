#include "ocp/asio_executor.hpp"

#include <algorithm>

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
  arm();
  return id;
}

void AsioExecutor::cancel(TimerId id) {
  const auto found = deadline_by_id_.find(id);
  if (found == deadline_by_id_.end()) {
    return;
  }
  queue_.erase(QueueKey{found->second, id});
  deadline_by_id_.erase(found);
  arm();
}

void AsioExecutor::arm() {
  if (queue_.empty()) {
    if (armed_for_) {
      armed_for_.reset();
      ++wait_generation_;
      timer_.cancel();
    }
    return;
  }
  const SimTime earliest = queue_.begin()->first.first;
  if (armed_for_ && *armed_for_ == earliest) {
    return;
  }
  armed_for_ = earliest;
  const std::uint64_t generation = ++wait_generation_;
  // expires_at cancels the previous wait; its handler (aborted, or already queued as a
  // success) is recognised as stale by its generation.
  timer_.expires_at(to_steady(earliest));
  timer_.async_wait([this, generation, alive = alive_](const boost::system::error_code& error) {
    if (!*alive || error == boost::asio::error::operation_aborted ||
        generation != wait_generation_) {
      return;
    }
    armed_for_.reset();
    run_due();
    if (*alive) {
      arm();
    }
  });
}

void AsioExecutor::run_due() {
  // One task at a time: a task may schedule or cancel others, or even destroy this executor.
  // Only tasks due when the batch began run in it, so a task that keeps re-posting itself
  // cannot starve the rest of the io_context.
  const std::shared_ptr<bool> alive = alive_;
  const SimTime batch_end = now();
  while (*alive && !queue_.empty() && queue_.begin()->first.first <= batch_end) {
    auto first = queue_.begin();
    Task task = std::move(first->second);
    deadline_by_id_.erase(first->first.second);
    queue_.erase(first);
    task();
  }
}

}  // namespace ocp
