// ControlTicker: one timer for the control ticks of many Streamers (fleet scale). Slots,
// phases, members joining and leaving, and a Streamer on a ticker against one on its own timer.
#include <gtest/gtest.h>

#include <vector>

#include "ocp/virtual_executor.hpp"
#include "streamer/control_ticker.hpp"
#include "streamer_harness.hpp"

namespace ocp::streamer_test {
namespace {

constexpr Micros period{10'000};

struct Ticks {
  std::vector<SimTime> deadlines, at;
  ControlTicker::TickHandler handler(VirtualExecutor& executor) {
    return [this, &executor](SimTime deadline) {
      deadlines.push_back(deadline);
      at.push_back(executor.now());
    };
  }
};

TEST(ControlTicker, OneSlotTicksEveryMemberOnTheFirstMembersAbsoluteDeadlines) {
  VirtualExecutor executor;
  executor.run_until(SimTime{Micros{3'000}});
  ControlTicker ticker(executor, period);
  Ticks first, second;
  ticker.add(first.handler(executor));
  executor.run_until(SimTime{Micros{15'000}});
  ticker.add(second.handler(executor));   // joins the phase: next tick at 23 ms
  executor.run_until(SimTime{Micros{40'000}});

  EXPECT_EQ(first.deadlines, (std::vector<SimTime>{SimTime{Micros{3'000}}, SimTime{Micros{13'000}},
                                                   SimTime{Micros{23'000}}, SimTime{Micros{33'000}}}));
  EXPECT_EQ(second.deadlines, (std::vector<SimTime>{SimTime{Micros{23'000}}, SimTime{Micros{33'000}}}));
  EXPECT_EQ(first.at, first.deadlines);   // on time: nothing else runs on this executor
}

TEST(ControlTicker, SlotsSpreadTheMembersOverThePeriod) {
  VirtualExecutor executor;
  ControlTicker ticker(executor, period, 4);
  std::vector<Ticks> members(5);
  for (auto& member : members) ticker.add(member.handler(executor));
  executor.run_until(SimTime{Micros{19'999}});

  // Member j in slot j mod 4, offset by 2.5 ms per slot.
  EXPECT_EQ(members[0].deadlines, (std::vector<SimTime>{SimTime{0}, SimTime{Micros{10'000}}}));
  EXPECT_EQ(members[1].deadlines, (std::vector<SimTime>{SimTime{Micros{2'500}}, SimTime{Micros{12'500}}}));
  EXPECT_EQ(members[2].deadlines, (std::vector<SimTime>{SimTime{Micros{5'000}}, SimTime{Micros{15'000}}}));
  EXPECT_EQ(members[3].deadlines, (std::vector<SimTime>{SimTime{Micros{7'500}}, SimTime{Micros{17'500}}}));
  EXPECT_EQ(members[4].deadlines, members[0].deadlines);
}

TEST(ControlTicker, APhaseShiftsEverySlotAndIsClampedToThePeriod) {
  VirtualExecutor executor;
  executor.run_until(SimTime{Micros{3'000}});
  ControlTicker shifted(executor, period, 2, Micros{1'250});
  Ticks first, second;
  shifted.add(first.handler(executor));
  shifted.add(second.handler(executor));
  executor.run_until(SimTime{Micros{20'000}});
  // t0 = 3 ms (the first add) + 1.25 ms; slot 1 half a period later.
  EXPECT_EQ(first.deadlines, (std::vector<SimTime>{SimTime{Micros{4'250}}, SimTime{Micros{14'250}}}));
  EXPECT_EQ(second.deadlines, (std::vector<SimTime>{SimTime{Micros{9'250}}, SimTime{Micros{19'250}}}));
  EXPECT_EQ(first.at, first.deadlines);

  // Below 0: none; a period or more: just under one period.
  for (const auto& [phase, offset] : {std::pair{Micros{-5}, Micros{0}}, std::pair{period, period - Micros{1}},
                                      std::pair{Micros{1'000'000}, period - Micros{1}}}) {
    ControlTicker clamped(executor, period, 1, phase);
    Ticks ticks;
    const SimTime added_at = executor.now();
    clamped.add(ticks.handler(executor));
    executor.run_until(added_at + period);
    ASSERT_FALSE(ticks.deadlines.empty()) << phase.count();
    EXPECT_EQ(ticks.deadlines.front(), added_at + offset) << phase.count();
  }
}

TEST(ControlTicker, RemovedMembersStopTickingAndAnEmptyTickerStopsItsTimer) {
  VirtualExecutor executor;
  ControlTicker ticker(executor, period);
  Ticks kept, removed_in_tick;
  ControlTicker::Member victim;
  ticker.add([&](SimTime deadline) {
    kept.deadlines.push_back(deadline);
    if (deadline == SimTime{Micros{10'000}}) ticker.remove(victim);   // from inside a tick
  });
  victim = ticker.add(removed_in_tick.handler(executor));
  executor.run_until(SimTime{Micros{30'000}});
  EXPECT_EQ(kept.deadlines.size(), 4u);
  EXPECT_EQ(removed_in_tick.deadlines, std::vector<SimTime>{SimTime{0}});   // removed before its 10 ms tick
  EXPECT_EQ(ticker.members(), 1u);

  ControlTicker lone(executor, period);
  Ticks once;
  const auto member = lone.add(once.handler(executor));
  executor.run_until(SimTime{Micros{30'000}});
  lone.remove(member);
  ticker.remove(ControlTicker::Member{});   // not a member: harmless
  EXPECT_EQ(lone.members(), 0u);
  ASSERT_EQ(once.deadlines.size(), 1u);
  executor.run_until(SimTime{Micros{100'000}});
  EXPECT_EQ(once.deadlines.size(), 1u);
}

TEST(ControlTicker, MembersAddedInsideATickJoinFromTheNextDeadline) {
  VirtualExecutor executor;
  ControlTicker ticker(executor, period);
  std::vector<Ticks> joined(32);   // enough to move the slot's storage if they went straight in
  Ticks founder;
  bool added = false;
  ticker.add([&](SimTime deadline) {
    founder.deadlines.push_back(deadline);
    if (added) return;
    added = true;
    for (auto& member : joined) ticker.add(member.handler(executor));
  });
  executor.run_until(SimTime{Micros{25'000}});
  EXPECT_EQ(founder.deadlines.size(), 3u);
  for (const auto& member : joined) {
    EXPECT_EQ(member.deadlines, (std::vector<SimTime>{SimTime{Micros{10'000}}, SimTime{Micros{20'000}}}));
  }
  EXPECT_EQ(ticker.members(), 33u);
}

TEST(ControlTicker, AStreamerOnATickerSendsWhatItSendsOnItsOwnTimer) {
  auto run = [](bool shared) {
    StreamerHarness harness;
    ControlTicker ticker(harness.executor, harness.core.config().control_period, 10);
    if (shared) harness.core.use_control_ticker(&ticker);
    TestVehicle& vehicle = harness.connect_vehicle();
    harness.core.start();
    harness.executor.run_until(ms(500));
    harness.core.stop();
    return std::make_pair(vehicle.received_at, harness.core.stats().control_frames_sent);
  };
  const auto own = run(false);
  const auto shared = run(true);
  EXPECT_EQ(own.second, 51u);
  EXPECT_EQ(shared, own);
}

}  // namespace
}  // namespace ocp::streamer_test
