// World::start when it fails: it leaves the World as it found it, so that the cause can be
// removed and start() called again, and the Player keeps no link to parts the World destroyed.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "world_fixture.hpp"

namespace ocp::world_test {
namespace {

TEST(WorldStart, AFailedStartCanBeRetriedOnceTheCauseIsRemoved) {
  VirtualWorld sim(one_vehicle_config());
  sim.world().set_streamer_threads({StreamerThread{&sim.executor(), nullptr}}, [](std::function<void()>) {});
  const Status refused = sim.start();
  ASSERT_FALSE(refused);
  EXPECT_EQ(refused.error().detail, "a Streamer thread without an executor or a poster");

  sim.world().set_streamer_threads({}, {});   // back to every part on the World's executor
  const Status retried = sim.start();
  ASSERT_TRUE(retried) << retried.error().message();
  EXPECT_TRUE(sim.world().running());
  EXPECT_EQ(sim.world().vehicles(), std::vector<std::string>{"truck-1"});
  sim.run_for(Millis{500});
  EXPECT_TRUE(sim.world().streamer("truck-1").latency_ms().has_value()) << "the retried world's loop did not close";

  const Status again = sim.start();
  ASSERT_FALSE(again) << "a second start after a successful one";
  EXPECT_EQ(again.error().detail, "world already started");
}

// The Player refuses the second vehicle (no fleet) after it linked the first; the World then
// destroys the first vehicle's parts, so the Player must not keep its link.
TEST(WorldStart, AVehicleThePlayerRefusesLeavesThePlayerWithoutTheOthersLinks) {
  WorldConfig config = one_vehicle_config();
  config.vehicles.push_back(vehicle_spec("truck-2"));
  VirtualWorld sim(config);
  const Status refused = sim.start();
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().detail.find("without a fleet configuration"), std::string::npos) << refused.error().detail;
  EXPECT_TRUE(sim.world().vehicles().empty());
  EXPECT_TRUE(sim.world().player().vehicles().empty()) << "the Player still links a destroyed vehicle";

  // Nothing about the configuration changed: a retry is refused for the same reason, not
  // because the Player still has truck-1 from the first attempt.
  const Status retried = sim.start();
  ASSERT_FALSE(retried);
  EXPECT_EQ(retried.error().detail, refused.error().detail);

  // The Player's frame loop and pings walk its links: with one left to truck-1's destroyed
  // link they would send on freed memory (AddressSanitizer: heap-use-after-free).
  sim.world().player().start();
  sim.run_for(Millis{200});
  EXPECT_EQ(sim.world().player().stats().frames, 21u);   // 0, 10, …, 200 ms
  EXPECT_TRUE(sim.world().player().last_shared().vehicle_feedback.empty());
}

}  // namespace
}  // namespace ocp::world_test
