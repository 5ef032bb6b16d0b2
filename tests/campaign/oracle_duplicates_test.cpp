// Conservation with duplicates (issue #34 item 1): the oracle counts a message's copies from the
// link's own `duplicated` events, never from the time between two deliveries. In real time the
// two copies' timers fire microseconds apart; the oracle that took "the same message delivered
// again at the same instant" for a duplicate gave 4 false violations a run.
#include <gtest/gtest.h>

#include <algorithm>

#include "campaign/oracle.hpp"
#include "ocp/impairments.hpp"
#include "ocp/virtual_executor.hpp"
#include "scenario/parse.hpp"
#include "world/world.hpp"

namespace ocp::campaign {
namespace {

const char* const one_vehicle = R"(seed: 3
duration: 2s
world:
  vehicles: [{name: v1}]
expect:
  invariants: [default_controller_during_control_fault]
)";

// Feeds hand-made link events to an oracle attached to a world that never starts.
class LinkFeed {
 public:
  LinkFeed() : scenario_(scenario::parse_scenario(one_vehicle, "one_vehicle.yaml")),
               world_(executor_, WorldConfig{}, [](const LogRecord&) {}), oracle_(scenario_) {
    oracle_.attach(world_);
  }
  void duplicates(double probability) {
    impairments_.duplicate_probability = probability;
    publish(0, ImpairmentChange{LinkRoute::to_player, &impairments_});
  }
  void link(std::int64_t at_us, LinkOutcome outcome, std::uint64_t message) {
    LinkEvent event;
    event.route = LinkRoute::to_player;
    event.kind = LinkMessageKind::feedback;
    event.outcome = outcome;
    event.message_id = message;
    publish(at_us, event);
  }
  std::uint64_t conservation_violations() const {
    return static_cast<std::uint64_t>(std::count_if(oracle_.violations().begin(), oracle_.violations().end(),
                                                    [](const Violation& v) { return v.check == Check::conservation; }));
  }
  std::string first() const { return oracle_.violations().empty() ? "" : oracle_.violations().front().detail; }

 private:
  void publish(std::int64_t at_us, EventBody body) {
    world_.events().publish(Event{SimTime{at_us}, Component{ComponentKind::link, "v1"}, std::move(body)});
  }
  scenario::Scenario scenario_;
  VirtualExecutor executor_;
  World world_;
  Oracle oracle_;
  Impairments impairments_;
};

TEST(OracleDuplicates, TwoCopiesDeliveredMicrosecondsApartAreNoMiscount) {
  LinkFeed feed;
  feed.duplicates(0.5);
  feed.link(1000, LinkOutcome::sent, 7);
  feed.link(1000, LinkOutcome::duplicated, 7);
  feed.link(1000, LinkOutcome::sent, 8);
  feed.link(41'000, LinkOutcome::delivered, 7);
  feed.link(41'003, LinkOutcome::delivered, 8);   // another message between the two copies
  feed.link(41'009, LinkOutcome::delivered, 7);   // the copy, 9 µs after the first
  EXPECT_EQ(feed.conservation_violations(), 0u) << feed.first();
}

TEST(OracleDuplicates, ACopyNobodyAnnouncedIsAMiscountEvenAtTheSameInstant) {
  LinkFeed feed;
  feed.duplicates(0.5);
  feed.link(1000, LinkOutcome::sent, 7);
  feed.link(41'000, LinkOutcome::delivered, 7);
  feed.link(41'000, LinkOutcome::delivered, 7);
  EXPECT_EQ(feed.conservation_violations(), 1u);
  EXPECT_NE(feed.first().find("message 7 delivered but not in flight"), std::string::npos) << feed.first();
}

TEST(OracleDuplicates, AThirdDeliveryOfATwiceSentMessageIsAMiscount) {
  LinkFeed feed;
  feed.duplicates(0.5);
  feed.link(1000, LinkOutcome::sent, 7);
  feed.link(1000, LinkOutcome::duplicated, 7);
  for (const std::int64_t at : {41'000, 41'000, 41'000}) feed.link(at, LinkOutcome::delivered, 7);
  EXPECT_EQ(feed.conservation_violations(), 1u) << feed.first();
}

TEST(OracleDuplicates, ADuplicateOnALinkSetToDuplicateNoneIsAMiscount) {
  LinkFeed feed;
  feed.link(1000, LinkOutcome::sent, 7);
  feed.link(1000, LinkOutcome::duplicated, 7);
  EXPECT_EQ(feed.conservation_violations(), 1u);
  EXPECT_NE(feed.first().find("set to duplicate none"), std::string::npos) << feed.first();
}

}  // namespace
}  // namespace ocp::campaign
