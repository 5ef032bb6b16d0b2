#include <gtest/gtest.h>

#include <algorithm>
#include <functional>

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

// The executor against a model of its contract: every event runs at its deadline (or at once
// when that has passed), earlier deadlines first, equal ones in scheduling order, cancelled
// ones never. Thousands of events on a few shared deadlines (how a fleet looks), scheduled
// from inside tasks, at `now`, in the past, and cancelled often enough to force compaction.
TEST(VirtualExecutor, RunsEventsInDeadlineThenSchedulingOrderLikeAReferenceModel) {
  VirtualExecutor executor;
  std::uint64_t state = 12345;
  const auto next_random = [&state](std::uint64_t bound) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (state >> 33) % bound;
  };
  struct Scheduled {
    SimTime deadline;
    std::uint64_t order;  // scheduling order
    bool cancelled = false;
  };
  std::vector<Scheduled> model;  // indexed by event number
  std::vector<Executor::TimerId> ids;
  std::vector<std::pair<std::uint64_t, SimTime>> ran;  // event number, time it ran
  std::function<void(int)> schedule = [&](int depth) {
    const std::uint64_t number = model.size();
    // Mostly shared deadlines on a 10 ms grid, some at `now`, some in the past.
    const std::uint64_t kind = next_random(10);
    SimTime deadline = kind < 6   ? SimTime{static_cast<std::int64_t>(next_random(20)) * 10'000}
                       : kind < 9 ? executor.now()
                                  : executor.now() - 5ms;
    model.push_back(Scheduled{std::max(deadline, executor.now()), number});
    ids.push_back(executor.call_at(deadline, [&, number, depth] {
      ran.emplace_back(number, executor.now());
      if (depth < 3) {
        for (std::uint64_t i = next_random(3); i > 0; --i) schedule(depth + 1);
      }
      // Cancel a random earlier event (often one that already ran: harmless).
      const std::uint64_t victim = next_random(model.size());
      if (!model[victim].cancelled && std::find_if(ran.begin(), ran.end(), [&](const auto& entry) {
                                         return entry.first == victim;
                                       }) == ran.end()) {
        model[victim].cancelled = true;
      }
      executor.cancel(ids[victim]);
    }));
  };
  for (int i = 0; i < 3000; ++i) schedule(0);
  // Enough cancelled far-off events to make them the clear majority once (compaction).
  for (int i = 0; i < 5000; ++i) executor.cancel(executor.call_at(SimTime{1'000'000'000}, [] {}));
  executor.run_until(SimTime{10'000'000});

  std::vector<Scheduled> expected;
  for (const Scheduled& event : model) {
    if (!event.cancelled) expected.push_back(event);
  }
  std::stable_sort(expected.begin(), expected.end(), [](const Scheduled& left, const Scheduled& right) {
    return left.deadline < right.deadline;  // stable: equal deadlines keep scheduling order
  });
  ASSERT_EQ(ran.size(), expected.size());
  for (std::size_t i = 0; i < ran.size(); ++i) {
    ASSERT_EQ(ran[i].first, expected[i].order) << "event " << i;
    ASSERT_EQ(ran[i].second, expected[i].deadline) << "event " << i;
  }
  EXPECT_GT(ran.size(), 3000u);
  EXPECT_EQ(executor.pending(), 0u);
}

}  // namespace
}  // namespace ocp
