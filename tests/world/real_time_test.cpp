// The same World on the real-time executor (ARCHITECTURE.md property 2). Bounds are loose on
// purpose: a loaded 2-core machine may delay timers, never by seconds.
#include <gtest/gtest.h>

#include <boost/asio/io_context.hpp>

#include "ocp/asio/executor.hpp"
#include "world/stream_tap.hpp"
#include "world/world.hpp"

namespace ocp {
namespace {

TEST(WorldRealTime, SameWorldClosesTheLatencyLoopOnTheAsioExecutor) {
  boost::asio::io_context io;
  AsioExecutor executor(io);
  WorldConfig config;
  config.tap_vehicle_streams = true;   // deterministic_keys stays off: a CSPRNG key
  VehicleSpec vehicle;
  vehicle.name = "truck-1";
  config.vehicles.push_back(vehicle);
  World world(executor, config, make_null_sink());
  ASSERT_TRUE(world.start());

  io.run_for(std::chrono::milliseconds(1500));
  world.stop();

  const StreamerCore& streamer = world.streamer("truck-1");
  EXPECT_GT(streamer.stats().control_frames_sent, 50u);
  ASSERT_TRUE(streamer.latency_ms().has_value()) << "no valid pair came back in 1.5 s";
  EXPECT_LT(*streamer.latency_ms(), 500u);
  ASSERT_NE(world.vehicle_tap("truck-1"), nullptr);
  EXPECT_GT(world.vehicle_tap("truck-1")->control_messages(), 50u);
  EXPECT_GT(world.vehicle_client("truck-1")->stats().echo_responses_sent, 50u);
}

}  // namespace
}  // namespace ocp
