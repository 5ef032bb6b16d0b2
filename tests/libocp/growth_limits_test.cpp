// Everything that queues or grows has a named limit and a clear error (issue #37 item 4): the
// link's in-flight pool, the virtual executor's pending events, an event bus's subscribers.
#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "ocp/com_channel.hpp"
#include "ocp/event_bus.hpp"
#include "ocp/virtual_executor.hpp"

namespace ocp {
namespace {

using namespace std::chrono_literals;

TEST(GrowthLimits, ALinkDropsWhatWouldGoPastItsInFlightLimit) {
  VirtualExecutor executor;
  ComChannel channel(executor, 1);
  LinkDirection& link = channel.to_streamer();
  EXPECT_EQ(link.in_flight_limit(), LinkDirection::default_in_flight_limit);
  link.set_in_flight_limit(3);
  link.set_impairments(Impairments{.delay = 1h});
  std::vector<DropReason> drops;
  auto subscription = link.events().subscribe([&](const Event& event) {
    if (const auto* l = std::get_if<LinkEvent>(&event.body); l && l->outcome == LinkOutcome::dropped) drops.push_back(l->reason);
  });
  for (std::uint64_t i = 0; i < 5; ++i) link.send(Ping{i, SimTime{0}});
  EXPECT_EQ(link.counters().in_flight, 3u);
  EXPECT_EQ(link.counters().dropped, 2u);
  EXPECT_EQ(drops, (std::vector<DropReason>{DropReason::in_flight_limit, DropReason::in_flight_limit}));
  EXPECT_EQ(drop_reason_name(DropReason::in_flight_limit), "in_flight_limit");
  executor.run_for(2h);   // once delivered, there is room again
  link.send(Ping{9, SimTime{0}});
  EXPECT_EQ(link.counters().in_flight, 1u);
}

TEST(GrowthLimits, AnExecutorRefusesARunawaySchedule) {
  VirtualExecutor executor;
  executor.set_pending_limit(100);
  for (int i = 0; i < 100; ++i) executor.call_after(Micros{i}, [] {});
  try {
    executor.call_after(1s, [] {});
    FAIL() << "the 101st pending event was taken";
  } catch (const std::length_error& error) {
    EXPECT_NE(std::string(error.what()).find("100 events pending at once (the limit)"), std::string::npos) << error.what();
  }
  executor.run_for(1s);   // what ran frees its place
  EXPECT_NO_THROW(executor.call_after(1s, [] {}));
}

TEST(GrowthLimits, ABusRefusesSubscribersPastItsLimit) {
  EventBus bus;
  std::vector<EventBus::Subscription> kept;
  for (std::size_t i = 0; i < EventBus::max_subscribers; ++i) kept.push_back(bus.subscribe([](const Event&) {}));
  EXPECT_THROW((void)bus.subscribe([](const Event&) {}), std::length_error);
  kept.pop_back();   // a dropped subscription frees its place
  EXPECT_NO_THROW(kept.push_back(bus.subscribe([](const Event&) {})));
}

}  // namespace
}  // namespace ocp
