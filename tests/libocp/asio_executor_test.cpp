#include <gtest/gtest.h>

#include <algorithm>
#include <boost/asio/io_context.hpp>
#include <chrono>
#include <vector>

#include "ocp/asio/executor.hpp"

namespace ocp {
namespace {

using namespace std::chrono_literals;

TEST(AsioExecutor, NowStartsNearZeroAndAdvancesWithTheSteadyClock) {
  boost::asio::io_context io;
  const auto before_construction = std::chrono::steady_clock::now();
  AsioExecutor executor(io);
  const SimTime first = executor.now();
  // Time 0 is when the executor was built: right after, now() counts no more than the steady
  // time since just before (an origin at the clock's epoch, e.g. boot, would count far more).
  EXPECT_LE(first, std::chrono::duration_cast<SimTime>(std::chrono::steady_clock::now() - before_construction));
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

// The timer is armed for the next deadline before a batch runs; a task in that batch that
// schedules something sooner must still get it on time.
TEST(AsioExecutor, EarlierDeadlineScheduledInsideABatchRunsOnTime) {
  boost::asio::io_context io;
  AsioExecutor executor(io);
  const SimTime base = executor.now();
  std::vector<int> order;
  SimTime sooner_ran_at{};
  executor.call_at(base + 1ms, [&] {
    order.push_back(1);
    executor.call_at(base + 5ms, [&] {
      order.push_back(2);
      sooner_ran_at = executor.now();
    });
  });
  executor.call_at(base + 300ms, [&] { order.push_back(3); });
  io.run();
  EXPECT_EQ(order, (std::vector<int>{1, 2, 3}));
  EXPECT_GE(sooner_ran_at, base + 5ms);
  EXPECT_LT(sooner_ran_at, base + 250ms);  // not held back until the later deadline
}

// A deadline that passes while a batch runs is not left for the timer to notice later.
TEST(AsioExecutor, DeadlinePassedDuringABatchRunsRightAfterIt) {
  boost::asio::io_context io;
  AsioExecutor executor(io);
  const SimTime base = executor.now();
  SimTime overtaken_ran_at{};
  bool late_ran = false;
  executor.call_at(base + 1ms, [&] {
    while (executor.now() < base + 6ms) {
    }
  });
  executor.call_at(base + 3ms, [&] { overtaken_ran_at = executor.now(); });
  executor.call_at(base + 300ms, [&] {
    late_ran = true;
    EXPECT_GT(overtaken_ran_at, SimTime{0});
  });
  io.run();
  EXPECT_TRUE(late_ran);
  EXPECT_GE(overtaken_ran_at, base + 6ms);
  EXPECT_LT(overtaken_ran_at, base + 250ms);
}

// Cancelling the earliest task leaves the timer armed for it; the wake-up that finds nothing
// due must still lead to the next task.
TEST(AsioExecutor, CancellingTheEarliestTaskKeepsTheRestOnSchedule) {
  boost::asio::io_context io;
  AsioExecutor executor(io);
  const SimTime base = executor.now();
  const auto earliest = executor.call_at(base + 2ms, [] { ADD_FAILURE() << "cancelled task ran"; });
  SimTime next_ran_at{};
  executor.call_at(base + 20ms, [&] { next_ran_at = executor.now(); });
  executor.cancel(earliest);
  io.run();
  EXPECT_GE(next_ran_at, base + 20ms);
  EXPECT_LT(next_ran_at, base + 2s);
}

// call_at_or_later: a task with slack runs at the next wake-up the executor has anyway.
TEST(AsioExecutor, ATaskWithSlackRidesOnTheNextWakeUpOfAnotherTask) {
  boost::asio::io_context io;
  AsioExecutor executor(io);
  const SimTime base = executor.now();
  std::vector<int> order;
  SimTime lenient_ran_at{};
  executor.call_at_or_later(base + 5ms, 2s, [&] {
    order.push_back(1);
    lenient_ran_at = executor.now();
  });
  executor.call_at(base + 30ms, [&] { order.push_back(2); });
  io.run();
  EXPECT_EQ(order, (std::vector<int>{1, 2}));
  EXPECT_GE(lenient_ran_at, base + 30ms);   // not a wake-up of its own at 5 ms
  EXPECT_LT(lenient_ran_at, base + 2s);
}

TEST(AsioExecutor, ATaskWithSlackRunsByItsLatestInstantWhenNothingElseWakes) {
  boost::asio::io_context io;
  AsioExecutor executor(io);
  const SimTime base = executor.now();
  SimTime ran_at{};
  executor.call_at_or_later(base + 5ms, 20ms, [&] { ran_at = executor.now(); });
  executor.call_at(base + 3s, [] {});   // a later strict task does not hold it back
  const auto started = std::chrono::steady_clock::now();
  io.run_one();
  EXPECT_GE(ran_at, base + 25ms);
  EXPECT_LT(std::chrono::steady_clock::now() - started, 2s);
}

TEST(AsioExecutor, TasksWithAndWithoutSlackRunInDeadlineThenSchedulingOrder) {
  boost::asio::io_context io;
  AsioExecutor executor(io);
  const SimTime base = executor.now();
  std::vector<int> order;
  executor.call_at_or_later(base + 5ms, 1s, [&] { order.push_back(1); });
  executor.call_at(base + 10ms, [&] { order.push_back(2); });
  executor.call_at_or_later(base + 10ms, 1s, [&] { order.push_back(3); });
  executor.call_at(base + 20ms, [&] { order.push_back(4); });
  executor.call_at_or_later(base + 40ms, 5ms, [&] { order.push_back(5); });
  io.run();
  EXPECT_EQ(order, (std::vector<int>{1, 2, 3, 4, 5}));
}

TEST(AsioExecutor, ACancelledTaskWithSlackNeverRunsNorHoldsTheIoContext) {
  boost::asio::io_context io;
  AsioExecutor executor(io);
  const SimTime base = executor.now();
  const auto cancelled = executor.call_at_or_later(base + 1ms, 10s, [] { ADD_FAILURE() << "cancelled task ran"; });
  bool other_ran = false;
  executor.call_at(base + 5ms, [&] { other_ran = true; });
  executor.cancel(cancelled);
  const auto started = std::chrono::steady_clock::now();
  io.run();
  EXPECT_TRUE(other_ran);
  EXPECT_LT(std::chrono::steady_clock::now() - started, 5s);   // not the 10 s slack
}

// A task's slot is reused once it ran or was cancelled; its old id must not reach the new task.
TEST(AsioExecutor, AStaleIdNeverCancelsTheTaskThatReusedItsSlot) {
  boost::asio::io_context io;
  AsioExecutor executor(io);
  const auto cancelled = executor.call_after(1ms, [] { ADD_FAILURE() << "cancelled task ran"; });
  executor.cancel(cancelled);
  int ran = 0;
  const auto ran_once = executor.post([&] { ++ran; });
  io.run();
  io.restart();
  const auto reuser = executor.call_after(1ms, [&] { ran += 10; });
  EXPECT_NE(reuser, cancelled);
  EXPECT_NE(reuser, ran_once);
  executor.cancel(cancelled);
  executor.cancel(ran_once);
  io.run();
  EXPECT_EQ(ran, 11);
}

// A timeout pushed back by every message: cancelled far-future tasks by the hundred thousand,
// swept while live tasks, scheduled among them with deadlines out of order, wait. The live ones
// still run in deadline order, and nothing cancelled holds the io_context.
TEST(AsioExecutor, ATimeoutRearmedOverAndOverKeepsOrderAndLetsTheIoContextEnd) {
  boost::asio::io_context io;
  AsioExecutor executor(io);
  const SimTime base = executor.now();
  std::vector<int> order;
  std::vector<std::pair<SimTime, int>> expected;
  Executor::TimerId timeout = 0;
  for (int i = 0; i < 100'000; ++i) {
    executor.cancel(timeout);
    timeout = executor.call_at(base + 1h + Micros{i}, [] { ADD_FAILURE() << "a cancelled timeout ran"; });
    if (i % 500 == 0) {
      // Far enough ahead that the churn cannot pass it (a past deadline would run in
      // scheduling order, by design); a scrambled, distinct offset for each.
      const SimTime deadline = base + 3s + Micros{(i / 500) * 7919 % 1000};
      expected.emplace_back(deadline, i);
      executor.call_at(deadline, [&order, i] { order.push_back(i); });
    }
  }
  executor.cancel(timeout);
  std::sort(expected.begin(), expected.end());
  std::vector<int> expected_order;
  for (const auto& [deadline, i] : expected) expected_order.push_back(i);
  const auto started = std::chrono::steady_clock::now();
  io.run();
  EXPECT_EQ(order, expected_order);
  EXPECT_LT(std::chrono::steady_clock::now() - started, 30s);   // not the hour
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
