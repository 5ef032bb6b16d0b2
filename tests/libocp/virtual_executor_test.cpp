#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "ocp/virtual_executor.hpp"

namespace ocp {
namespace {

using namespace std::chrono_literals;

TEST(VirtualExecutor, TimersFireInDeadlineOrderAtExactTimes) {
  VirtualExecutor executor;
  std::vector<std::pair<int, SimTime>> fired;
  executor.call_at(SimTime{300}, [&] { fired.emplace_back(3, executor.now()); });
  executor.call_at(SimTime{100}, [&] { fired.emplace_back(1, executor.now()); });
  executor.call_at(SimTime{200}, [&] { fired.emplace_back(2, executor.now()); });
  executor.run_until(SimTime{1000});
  ASSERT_EQ(fired.size(), 3u);
  EXPECT_EQ(fired[0], std::make_pair(1, SimTime{100}));
  EXPECT_EQ(fired[1], std::make_pair(2, SimTime{200}));
  EXPECT_EQ(fired[2], std::make_pair(3, SimTime{300}));
  EXPECT_EQ(executor.now(), SimTime{1000});
}

TEST(VirtualExecutor, EqualDeadlinesRunInSchedulingOrder) {
  VirtualExecutor executor;
  std::vector<int> order;
  for (int i = 0; i < 100; ++i) {
    executor.call_at(SimTime{50}, [&order, i] { order.push_back(i); });
  }
  executor.run_for(1ms);
  ASSERT_EQ(order.size(), 100u);
  for (int i = 0; i < 100; ++i) {
    EXPECT_EQ(order[i], i);
  }
}

TEST(VirtualExecutor, TasksCanScheduleTasks) {
  VirtualExecutor executor;
  std::vector<SimTime> times;
  std::function<void()> chain = [&] {
    times.push_back(executor.now());
    if (times.size() < 5) {
      executor.call_after(10us, chain);
    }
  };
  executor.post(chain);
  executor.run_until(SimTime{1000});
  EXPECT_EQ(times, (std::vector<SimTime>{SimTime{0}, SimTime{10}, SimTime{20}, SimTime{30}, SimTime{40}}));
}

TEST(VirtualExecutor, TaskScheduledForNowRunsAfterTasksAlreadyDueNow) {
  VirtualExecutor executor;
  std::vector<std::string> order;
  executor.call_at(SimTime{10}, [&] {
    order.push_back("a");
    executor.post([&] { order.push_back("c"); });
  });
  executor.call_at(SimTime{10}, [&] { order.push_back("b"); });
  executor.run_until(SimTime{10});
  EXPECT_EQ(order, (std::vector<std::string>{"a", "b", "c"}));
}

TEST(VirtualExecutor, CancelledTaskNeverRuns) {
  VirtualExecutor executor;
  bool ran = false;
  const auto id = executor.call_at(SimTime{100}, [&] { ran = true; });
  EXPECT_EQ(executor.pending(), 1u);
  executor.cancel(id);
  executor.cancel(id);  // harmless twice
  EXPECT_EQ(executor.pending(), 0u);
  executor.run_until(SimTime{200});
  EXPECT_FALSE(ran);
  EXPECT_EQ(executor.events_run(), 0u);
}

TEST(VirtualExecutor, CancellingAStaleIdDoesNotCancelTheTaskReusingItsSlot) {
  VirtualExecutor executor;
  const auto first = executor.call_at(SimTime{10}, [] {});
  executor.run_until(SimTime{10});
  bool second_ran = false;
  const auto second = executor.call_at(SimTime{20}, [&] { second_ran = true; });
  EXPECT_NE(first, second);
  executor.cancel(first);
  executor.run_until(SimTime{30});
  EXPECT_TRUE(second_ran);
}

TEST(VirtualExecutor, IdsAreNeverZero) {
  VirtualExecutor executor;
  for (int i = 0; i < 10; ++i) {
    EXPECT_NE(executor.post([] {}), 0u);
  }
}

TEST(VirtualExecutor, PastDeadlineRunsAtNowWithoutMovingTimeBackwards) {
  VirtualExecutor executor;
  executor.run_until(SimTime{500});
  SimTime ran_at{-1};
  executor.call_at(SimTime{100}, [&] { ran_at = executor.now(); });
  EXPECT_EQ(executor.next_deadline(), SimTime{500});
  EXPECT_TRUE(executor.step());
  EXPECT_EQ(ran_at, SimTime{500});
  EXPECT_EQ(executor.now(), SimTime{500});
}

TEST(VirtualExecutor, StepRunsOneEventAndReportsIdle) {
  VirtualExecutor executor;
  int runs = 0;
  executor.call_at(SimTime{7}, [&] { ++runs; });
  executor.call_at(SimTime{9}, [&] { ++runs; });
  EXPECT_EQ(executor.next_deadline(), SimTime{7});
  EXPECT_TRUE(executor.step());
  EXPECT_EQ(executor.now(), SimTime{7});
  EXPECT_EQ(runs, 1);
  EXPECT_TRUE(executor.step());
  EXPECT_EQ(executor.now(), SimTime{9});
  EXPECT_FALSE(executor.step());
  EXPECT_EQ(executor.next_deadline(), SimTime::max());
  EXPECT_EQ(executor.events_run(), 2u);
}

TEST(VirtualExecutor, NextDeadlineSkipsCancelledEvents) {
  VirtualExecutor executor;
  const auto early = executor.call_at(SimTime{5}, [] {});
  executor.call_at(SimTime{8}, [] {});
  executor.cancel(early);
  EXPECT_EQ(executor.next_deadline(), SimTime{8});
}

TEST(VirtualExecutor, RunUntilLeavesLaterEventsPending) {
  VirtualExecutor executor;
  int runs = 0;
  executor.call_at(SimTime{100}, [&] { ++runs; });
  executor.call_at(SimTime{101}, [&] { ++runs; });
  executor.run_until(SimTime{100});
  EXPECT_EQ(runs, 1);
  EXPECT_EQ(executor.pending(), 1u);
  EXPECT_EQ(executor.now(), SimTime{100});
}

TEST(VirtualExecutor, DriveBoundedStopsAfterMaxSteps) {
  VirtualExecutor executor;
  std::function<void()> forever = [&] { executor.call_after(1us, forever); };
  executor.post(forever);
  EXPECT_EQ(executor.drive_bounded(1000), 1000u);
  EXPECT_EQ(executor.now(), SimTime{999});
  VirtualExecutor idle;
  idle.post([] {});
  EXPECT_EQ(idle.drive_bounded(1000), 1u);
}

std::vector<std::pair<int, SimTime>> run_pseudo_random_world() {
  VirtualExecutor executor;
  std::vector<std::pair<int, SimTime>> trace;
  std::uint64_t state = 12345;
  auto next_random = [&state] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return state >> 33;
  };
  std::vector<Executor::TimerId> ids;
  for (int i = 0; i < 2000; ++i) {
    ids.push_back(executor.call_at(SimTime{static_cast<std::int64_t>(next_random() % 10000)}, [&, i] {
      trace.emplace_back(i, executor.now());
      if (i % 3 == 0) {
        executor.call_after(Micros{static_cast<std::int64_t>(next_random() % 50)},
                            [&, i] { trace.emplace_back(-i, executor.now()); });
      }
    }));
  }
  for (std::size_t i = 0; i < ids.size(); i += 7) {
    executor.cancel(ids[i]);
  }
  executor.run_until(SimTime{20000});
  return trace;
}

TEST(VirtualExecutor, TwoIdenticalRunsGiveIdenticalSequences) {
  const auto first = run_pseudo_random_world();
  const auto second = run_pseudo_random_world();
  EXPECT_GT(first.size(), 2000u);
  EXPECT_EQ(first, second);
  for (std::size_t i = 1; i < first.size(); ++i) {
    ASSERT_LE(first[i - 1].second, first[i].second);
  }
}

TEST(VirtualExecutor, LongRunKeepsPendingWorkBounded) {
  // A watchdog re-armed on every message (cancel + call_after) must not pile up state.
  VirtualExecutor executor;
  Executor::TimerId watchdog = 0;
  std::function<void()> message = [&] {
    executor.cancel(watchdog);
    watchdog = executor.call_after(2s, [] {});
    executor.call_after(10ms, message);
  };
  executor.post(message);
  executor.run_for(std::chrono::hours{1});
  EXPECT_EQ(executor.pending(), 2u);
  EXPECT_EQ(executor.events_run(), 360001u);  // t = 0, 10 ms, …, 3600 s
}

}  // namespace
}  // namespace ocp
