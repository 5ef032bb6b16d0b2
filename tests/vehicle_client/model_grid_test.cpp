// VehicleClientConfig::model_grid: the model timer's phase. 0 (the default): model ticks at
// attach + k·model_step. > 0: at the multiples of the grid on the executor's timeline, so the
// clients one process hosts share their tick instants (fewer wake-ups). Virtual time, exact.
#include <gtest/gtest.h>
#include <rapidjson/document.h>

#include <vector>

#include "ocp/log.hpp"
#include "ocp/pipe.hpp"
#include "ocp/virtual_executor.hpp"
#include "streamer_peer.hpp"
#include "vehicle_client/vehicle_client.hpp"

namespace ocp {
namespace {

std::int64_t user_data_sequence(const VehicleClient& client) {
  rapidjson::Document document;
  document.Parse(client.user_data_json().c_str());
  EXPECT_FALSE(document.HasParseError()) << client.user_data_json();
  return document["sequence"].GetInt64();
}

// Attaches a client at `attach_at` and returns the instants (µs) of its model ticks up to
// `until`, seen as the user data's sequence changing (one refresh per model tick).
std::vector<std::int64_t> model_tick_instants(VehicleClientConfig config, Micros attach_at, Micros until) {
  VirtualExecutor executor;
  executor.run_for(attach_at);
  VehicleClient client(executor, config, Logger(executor, "vehicle-client", make_null_sink()));
  testing::StreamerPeer streamer(executor);
  PipeEnds pipe = make_pipe(executor, {});
  streamer.attach(pipe.a);
  client.attach(pipe.b);
  std::vector<std::int64_t> instants;
  std::int64_t sequence = user_data_sequence(client);
  while (executor.now() < SimTime{until}) {
    executor.run_for(Micros{100});
    if (const std::int64_t now = user_data_sequence(client); now != sequence) {
      instants.push_back(executor.now().count());
      sequence = now;
    }
  }
  return instants;
}

TEST(VehicleClientModelGrid, WithoutAGridTheModelTicksFromAttach) {
  const auto instants = model_tick_instants(VehicleClientConfig{}, Micros{3'300}, Micros{40'000});
  EXPECT_EQ(instants, (std::vector<std::int64_t>{13'300, 23'300, 33'300}));
}

TEST(VehicleClientModelGrid, WithAGridTheModelTicksOnItsMultiplesFromOneStepAfterAttach) {
  VehicleClientConfig config;
  config.model_grid = Micros{1'000};
  // attach 3.3 ms: the first tick at the first multiple of 1 ms at or after 13.3 ms.
  EXPECT_EQ(model_tick_instants(config, Micros{3'300}, Micros{40'000}),
            (std::vector<std::int64_t>{14'000, 24'000, 34'000}));
  config.model_grid = Micros{10'000};
  EXPECT_EQ(model_tick_instants(config, Micros{3'300}, Micros{40'000}),
            (std::vector<std::int64_t>{20'000, 30'000, 40'000}));
  // Already on the grid: one model step after attach, as without one.
  EXPECT_EQ(model_tick_instants(config, Micros{10'000}, Micros{40'000}),
            (std::vector<std::int64_t>{20'000, 30'000, 40'000}));
}

TEST(VehicleClientModelGrid, ANegativeGridIsRefused) {
  VehicleClientConfig config;
  config.model_grid = Micros{-1};
  ASSERT_TRUE(validate(config));
  EXPECT_NE(validate(config)->find("model grid"), std::string::npos);
  config.model_grid = Micros{0};
  EXPECT_FALSE(validate(config));
}

}  // namespace
}  // namespace ocp
