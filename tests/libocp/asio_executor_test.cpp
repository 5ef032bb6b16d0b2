#include <gtest/gtest.h>

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <vector>

#include "ocp/asio_executor.hpp"

namespace ocp {
namespace {

using namespace std::chrono_literals;

TEST(AsioExecutor, NowStartsNearZeroAndAdvancesWithTheSteadyClock) {
  boost::asio::io_context io;
  AsioExecutor executor(io);
  const SimTime first = executor.now();
  EXPECT_GE(first, SimTime{0});
  EXPECT_LT(first, 2s);
  const auto before = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - before < 2ms) {
  }
  EXPECT_GE(executor.now() - first, 2ms);
}

TEST(AsioExecutor, TimerFiresNotBeforeItsDeadline) {
  boost::asio::io_context io;
  AsioExecutor executor(io);
  const auto start = std::chrono::steady_clock::now();
  std::chrono::steady_clock::duration fired_after{};
  SimTime fired_now{};
  const SimTime deadline = executor.now() + 20ms;
  executor.call_at(deadline, [&] {
    fired_after = std::chrono::steady_clock::now() - start;
    fired_now = executor.now();
  });
  io.run();
  EXPECT_GE(fired_after, 20ms);
  EXPECT_LT(fired_after, 2s);
  EXPECT_GE(fired_now, deadline);
}

TEST(AsioExecutor, TasksRunInDeadlineThenSchedulingOrder) {
  boost::asio::io_context io;
  AsioExecutor executor(io);
  std::vector<int> order;
  const SimTime base = executor.now();
  executor.call_at(base + 30ms, [&] { order.push_back(4); });
  executor.call_at(base + 10ms, [&] { order.push_back(1); });
  executor.call_at(base + 20ms, [&] { order.push_back(2); });
  executor.call_at(base + 20ms, [&] { order.push_back(3); });
  io.run();
  EXPECT_EQ(order, (std::vector<int>{1, 2, 3, 4}));
}

TEST(AsioExecutor, PastDeadlineRunsSoonAfterTasksAlreadyDue) {
  boost::asio::io_context io;
  AsioExecutor executor(io);
  std::vector<int> order;
  executor.post([&] { order.push_back(1); });
  executor.call_at(SimTime{0}, [&] { order.push_back(2); });
  io.run();
  EXPECT_EQ(order, (std::vector<int>{1, 2}));
}

TEST(AsioExecutor, CancelledTaskNeverRuns) {
  boost::asio::io_context io;
  AsioExecutor executor(io);
  bool cancelled_ran = false;
  bool other_ran = false;
  const auto id = executor.call_after(5ms, [&] { cancelled_ran = true; });
  executor.call_after(10ms, [&] { other_ran = true; });
  executor.cancel(id);
  executor.cancel(id);
  io.run();
  EXPECT_FALSE(cancelled_ran);
  EXPECT_TRUE(other_ran);
}

TEST(AsioExecutor, IoContextRunsOutOfWorkWhenEverythingIsCancelled) {
  boost::asio::io_context io;
  AsioExecutor executor(io);
  const auto id = executor.call_after(10s, [] {});
  executor.cancel(id);
  const auto start = std::chrono::steady_clock::now();
  io.run();
  EXPECT_LT(std::chrono::steady_clock::now() - start, 2s);
}

TEST(AsioExecutor, ManyShortTimersAllFireAndChainsWork) {
  boost::asio::io_context io;
  AsioExecutor executor(io);
  int fired = 0;
  std::function<void()> chain = [&] {
    if (++fired < 200) {
      executor.call_after(100us, chain);
    }
  };
  executor.post(chain);
  io.run();
  EXPECT_EQ(fired, 200);
}

TEST(AsioExecutor, DestroyedExecutorLeavesNoRunnableTasks) {
  boost::asio::io_context io;
  bool ran = false;
  {
    AsioExecutor executor(io);
    executor.post([&] { ran = true; });
  }
  io.run();
  EXPECT_FALSE(ran);
}

}  // namespace
}  // namespace ocp
