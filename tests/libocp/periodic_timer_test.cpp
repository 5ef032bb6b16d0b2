#include <gtest/gtest.h>

#include <vector>

#include "ocp/executor.hpp"
#include "ocp/virtual_executor.hpp"

namespace ocp {
namespace {

using namespace std::chrono_literals;

// Runs every task `lateness` after its deadline, as a busy real-time executor would.
class LateExecutor final : public Executor {
 public:
  explicit LateExecutor(VirtualExecutor& inner) : inner_(inner) {}
  SimTime now() const override { return inner_.now(); }
  TimerId call_at(SimTime deadline, Task task) override {
    return inner_.call_at(deadline + lateness, std::move(task));
  }
  void cancel(TimerId id) override { inner_.cancel(id); }
  Micros lateness{0};

 private:
  VirtualExecutor& inner_;
};

TEST(PeriodicTimer, TicksAtExactAbsoluteDeadlinesWithoutDrift) {
  VirtualExecutor executor;
  std::vector<std::pair<SimTime, SimTime>> ticks;  // (deadline, now)
  PeriodicTimer timer(executor, 10ms, [&](SimTime deadline) { ticks.emplace_back(deadline, executor.now()); });
  timer.start(SimTime{1234});
  executor.run_until(SimTime{1234} + 10ms * 1000);
  ASSERT_EQ(ticks.size(), 1001u);
  for (std::size_t k = 0; k < ticks.size(); ++k) {
    ASSERT_EQ(ticks[k].first, SimTime{1234} + 10ms * static_cast<int>(k));
    ASSERT_EQ(ticks[k].second, ticks[k].first);
  }
  EXPECT_EQ(ticks[1000].first, SimTime{10'001'234});
  EXPECT_EQ(timer.ticks(), 1001u);
  EXPECT_EQ(timer.missed_ticks(), 0u);
}

TEST(PeriodicTimer, StopInsideATickEndsTicking) {
  VirtualExecutor executor;
  int count = 0;
  PeriodicTimer* self = nullptr;
  PeriodicTimer timer(executor, 5ms, [&](SimTime) {
    if (++count == 3) {
      self->stop();
    }
  });
  self = &timer;
  timer.start(SimTime{0});
  executor.run_for(1s);
  EXPECT_EQ(count, 3);
  EXPECT_FALSE(timer.running());
  EXPECT_EQ(executor.pending(), 0u);
}

TEST(PeriodicTimer, RestartInsideATickUsesTheNewPhase) {
  VirtualExecutor executor;
  std::vector<SimTime> deadlines;
  PeriodicTimer* self = nullptr;
  PeriodicTimer timer(executor, 10ms, [&](SimTime deadline) {
    deadlines.push_back(deadline);
    if (deadlines.size() == 2) {
      self->stop();
      self->start(deadline + 3ms);
    }
  });
  self = &timer;
  timer.start(SimTime{0});
  executor.run_until(SimTime{40'000});
  EXPECT_EQ(deadlines, (std::vector<SimTime>{0ms, 10ms, 13ms, 23ms, 33ms}));
}

TEST(PeriodicTimer, StopBeforeFirstTickPreventsAllTicks) {
  VirtualExecutor executor;
  int count = 0;
  PeriodicTimer timer(executor, 1ms, [&](SimTime) { ++count; });
  timer.start(SimTime{100});
  EXPECT_TRUE(timer.running());
  timer.stop();
  executor.run_for(10ms);
  EXPECT_EQ(count, 0);
}

TEST(PeriodicTimer, DestroyingTheTimerCancelsItsPendingTick) {
  VirtualExecutor executor;
  int count = 0;
  {
    PeriodicTimer timer(executor, 1ms, [&](SimTime) { ++count; });
    timer.start(SimTime{100});
  }
  executor.run_for(10ms);
  EXPECT_EQ(count, 0);
  EXPECT_EQ(executor.pending(), 0u);
}

TEST(PeriodicTimer, StartedInThePastSkipsMissedTicksInsteadOfBunching) {
  VirtualExecutor executor;
  executor.run_until(SimTime{95'000});
  std::vector<std::pair<SimTime, SimTime>> ticks;
  PeriodicTimer timer(executor, 10ms, [&](SimTime deadline) { ticks.emplace_back(deadline, executor.now()); });
  timer.start(SimTime{0});
  executor.run_until(SimTime{120'000});
  // Tick 0 runs late at 95 ms; 10..90 ms are skipped; 100, 110, 120 ms run on time.
  ASSERT_EQ(ticks.size(), 4u);
  EXPECT_EQ(ticks[0], std::make_pair(SimTime{0}, SimTime{95'000}));
  EXPECT_EQ(ticks[1], std::make_pair(SimTime{100'000}, SimTime{100'000}));
  EXPECT_EQ(ticks[3], std::make_pair(SimTime{120'000}, SimTime{120'000}));
  EXPECT_EQ(timer.missed_ticks(), 9u);
}

TEST(PeriodicTimer, LatenessWithinAPeriodKeepsEveryTickAndThePhase) {
  VirtualExecutor inner;
  LateExecutor executor(inner);
  executor.lateness = 3ms;
  std::vector<SimTime> deadlines;
  PeriodicTimer timer(executor, 10ms, [&](SimTime deadline) { deadlines.push_back(deadline); });
  timer.start(SimTime{0});
  inner.run_until(SimTime{43'000});
  EXPECT_EQ(deadlines, (std::vector<SimTime>{0ms, 10ms, 20ms, 30ms, 40ms}));
  EXPECT_EQ(timer.missed_ticks(), 0u);
}

TEST(PeriodicTimer, LatenessBeyondAPeriodSkipsAndCountsMissedTicks) {
  VirtualExecutor inner;
  LateExecutor executor(inner);
  std::vector<std::pair<SimTime, SimTime>> ticks;
  PeriodicTimer timer(executor, 10ms, [&](SimTime deadline) {
    ticks.emplace_back(deadline, inner.now());
    // One slow stretch: the tick after 20 ms runs 25 ms late.
    executor.lateness = deadline == SimTime{10'000} ? 25ms : 0ms;
  });
  timer.start(SimTime{0});
  inner.run_until(SimTime{70'000});
  // 20 ms runs at 45 ms; 30 and 40 ms are skipped; 50 ms is next, on time again.
  ASSERT_GE(ticks.size(), 4u);
  EXPECT_EQ(ticks[2], std::make_pair(SimTime{20'000}, SimTime{45'000}));
  EXPECT_EQ(ticks[3], std::make_pair(SimTime{50'000}, SimTime{50'000}));
  EXPECT_EQ(timer.missed_ticks(), 2u);
  EXPECT_EQ(timer.ticks(), 6u);  // 0, 10, 20, 50, 60, 70 ms
}

}  // namespace
}  // namespace ocp
