// World::start when it fails: it leaves the World not started, so that the cause can be
// removed and start() called again.
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

}  // namespace
}  // namespace ocp::world_test
