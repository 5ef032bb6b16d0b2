#pragma once
// Real-time executor on a boost::asio::io_context: now() is steady_clock time since
// construction; call_at arms a steady_timer at the absolute deadline.
#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <memory>
#include <unordered_map>

#include "ocp/executor.hpp"

namespace ocp {

class AsioExecutor final : public Executor {
 public:
  explicit AsioExecutor(boost::asio::io_context& io);
  ~AsioExecutor() override;

  SimTime now() const override;
  TimerId call_at(SimTime deadline, Task task) override;
  void cancel(TimerId id) override;

  boost::asio::io_context& io() { return io_; }
  // Converts a SimTime on this executor's timeline to a steady_clock time point.
  std::chrono::steady_clock::time_point to_steady(SimTime t) const { return origin_ + t; }

 private:
  boost::asio::io_context& io_;
  std::chrono::steady_clock::time_point origin_;
  TimerId next_id_ = 1;
  std::unordered_map<TimerId, std::unique_ptr<boost::asio::steady_timer>> timers_;
};

}  // namespace ocp
