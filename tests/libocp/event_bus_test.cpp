// EventBus: any number of subscribers, RAII subscriptions that may come and go at any time
// (also from inside a handler), parent buses, and active() false when nobody listens.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "ocp/event_bus.hpp"

namespace ocp {
namespace {

Event gamepad_event(std::int64_t time_us) { return Event{SimTime{time_us}, Component{}, GamepadChange{true}}; }

TEST(EventBus, IsInactiveUntilSomebodySubscribesAndAfterTheyLeave) {
  EventBus bus;
  EXPECT_FALSE(bus.active());
  {
    auto subscription = bus.subscribe([](const Event&) {});
    EXPECT_TRUE(bus.active());
  }
  EXPECT_FALSE(bus.active());
}

TEST(EventBus, EverySubscriberGetsEveryEventInOrder) {
  EventBus bus;
  std::vector<std::int64_t> first;
  std::vector<std::int64_t> second;
  auto a = bus.subscribe([&](const Event& event) { first.push_back(event.time.count()); });
  auto b = bus.subscribe([&](const Event& event) { second.push_back(event.time.count()); });
  bus.publish(gamepad_event(1));
  bus.publish(gamepad_event(2));
  EXPECT_EQ(first, (std::vector<std::int64_t>{1, 2}));
  EXPECT_EQ(second, (std::vector<std::int64_t>{1, 2}));
}

TEST(EventBus, AHandlerMayUnsubscribeItselfAndOthersWhilePublishing) {
  EventBus bus;
  int first_calls = 0;
  int second_calls = 0;
  EventBus::Subscription second;
  EventBus::Subscription first = bus.subscribe([&](const Event&) {
    ++first_calls;
    first.reset();    // itself
    second.reset();   // and the one after it, before it ran
  });
  second = bus.subscribe([&](const Event&) { ++second_calls; });
  bus.publish(gamepad_event(1));
  bus.publish(gamepad_event(2));
  EXPECT_EQ(first_calls, 1);
  EXPECT_EQ(second_calls, 0);
  EXPECT_FALSE(bus.active());
}

TEST(EventBus, ASubscriberAddedWhilePublishingHearsFromTheNextEventOn) {
  EventBus bus;
  std::vector<std::int64_t> late;
  EventBus::Subscription added;
  auto adder = bus.subscribe([&](const Event&) {
    if (!added.active()) added = bus.subscribe([&](const Event& event) { late.push_back(event.time.count()); });
  });
  bus.publish(gamepad_event(1));
  bus.publish(gamepad_event(2));
  EXPECT_EQ(late, (std::vector<std::int64_t>{2}));
}

TEST(EventBus, EventsReachTheParentAfterTheChild) {
  EventBus world;
  EventBus streamer;
  streamer.set_parent(&world);
  EXPECT_FALSE(streamer.active());
  std::vector<const char*> order;
  auto at_world = world.subscribe([&](const Event&) { order.push_back("world"); });
  EXPECT_TRUE(streamer.active()) << "a listener up the chain makes the child active";
  auto at_streamer = streamer.subscribe([&](const Event&) { order.push_back("streamer"); });
  streamer.publish(gamepad_event(1));
  world.publish(gamepad_event(2));
  EXPECT_EQ(order, (std::vector<const char*>{"streamer", "world", "world"}));
}

TEST(EventBus, ASubscriptionMayOutliveItsBus) {
  auto bus = std::make_unique<EventBus>();
  auto subscription = bus->subscribe([](const Event&) {});
  bus.reset();
  EXPECT_FALSE(subscription.active());
  subscription.reset();   // no access to the destroyed bus
}

TEST(EventBus, MovingASubscriptionKeepsExactlyOneRegistration) {
  EventBus bus;
  int calls = 0;
  auto original = bus.subscribe([&](const Event&) { ++calls; });
  EventBus::Subscription moved = std::move(original);
  bus.publish(gamepad_event(1));
  EXPECT_EQ(calls, 1);
  moved.reset();
  EXPECT_FALSE(bus.active());
}

}  // namespace
}  // namespace ocp
