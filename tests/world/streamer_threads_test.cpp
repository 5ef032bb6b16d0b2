// Fleet scale in a World: a control ticker shared by the Streamers of an executor
// (WorldConfig::control_tick_slots) and Streamers placed on other threads
// (World::set_streamer_threads), whose link messages cross through a hand-over. The hand-over
// is exercised here in virtual time, with "threads" whose posters post to the same executor.
#include <gtest/gtest.h>

#include <map>
#include <optional>
#include <variant>

#include "world_fixture.hpp"

namespace ocp::world_test {
namespace {

std::string vehicle_name(int index) {
  std::string name = "v";
  name += std::to_string(index);   // (not "v" + …: GCC 12 -Wrestrict false positive)
  return name;
}

WorldConfig fleet_of(int vehicles, bool in_process_clients) {
  WorldConfig config;
  config.seed = 5;
  config.player.fleet = true;
  for (int index = 0; index < vehicles; ++index) {
    VehicleSpec spec = vehicle_spec(vehicle_name(index));
    spec.in_process_client = in_process_clients;
    config.vehicles.push_back(spec);
  }
  return config;
}

std::string trace_of(WorldConfig config) {
  config.vehicles[0].to_streamer = jittery_lossy_link();
  config.vehicles[0].to_player = jittery_lossy_link();
  VirtualWorld sim(config);
  EXPECT_TRUE(sim.start());
  sim.run_for(Millis{150});
  sim.world().drop_vehicle_connection(config.vehicles[0].name);
  sim.run_for(Millis{150});
  return sim.trace().jsonl();
}

TEST(WorldSharedTick, OneVehicleOnASharedTickerGivesTheSameTraceAsOnItsOwnTimer) {
  WorldConfig own = one_vehicle_config(77);
  WorldConfig shared = own;
  shared.control_tick_slots = 10;
  const std::string expected = trace_of(own);
  EXPECT_NE(expected.find(R"("event":"latency")"), std::string::npos);
  EXPECT_EQ(trace_of(shared), expected);
}

TEST(WorldSharedTick, SlotsSpreadTheFleetsTicksOverThePeriodAndEveryVehicleKeepsItsLoop) {
  WorldConfig config = fleet_of(4, true);
  config.control_tick_slots = 4;
  VirtualWorld sim(config);
  std::map<std::string, std::vector<SimTime>> ticks;
  auto subscription = sim.world().events().subscribe([&](const Event& event) {
    if (std::holds_alternative<LatencySample>(event.body)) ticks[std::string(event.component.name)].push_back(event.time);
  });
  ASSERT_TRUE(sim.start());
  sim.run_for(Millis{1000});
  for (int index = 0; index < 4; ++index) {
    const std::string name = vehicle_name(index);
    const auto& times = ticks[name];
    ASSERT_GE(times.size(), 99u) << name;
    EXPECT_EQ(times.front(), SimTime{Micros{2'500 * index}}) << name;
    for (std::size_t k = 1; k < times.size(); ++k) EXPECT_EQ(times[k] - times[k - 1], tick) << name;
    // The loop is closed for every vehicle (the fleet Player without a gamepad reports
    // OperatorStationHasError, which is not the Streamer's tick).
    const FaultSet& faults = sim.world().streamer(name).faults();
    for (const FaultId fault : {FaultId::NoControlMessage, FaultId::HighLatency, FaultId::InvalidMac,
                                FaultId::VehicleNoResponse}) {
      EXPECT_FALSE(faults.contains(fault)) << name << ": " << faults.fault_reason();
    }
  }
}

// Two "threads" that are the World's own executor: the wiring is the threaded one.
struct SameExecutorThreads {
  explicit SameExecutorThreads(VirtualWorld& sim) {
    auto post = [&sim](std::function<void()> task) {
      ++posts;
      sim.executor().post(std::move(task));
    };
    sim.world().set_streamer_threads({{&sim.executor(), post}, {&sim.executor(), post}}, post);
  }
  static inline int posts = 0;
};

// The World's executor under another address: a second "thread" with a ticker of its own, on
// the same virtual timeline.
class ExecutorView : public Executor {
 public:
  explicit ExecutorView(Executor& target) : target_(target) {}
  SimTime now() const override { return target_.now(); }
  TimerId call_at(SimTime deadline, Task task) override { return target_.call_at(deadline, std::move(task)); }
  void cancel(TimerId id) override { target_.cancel(id); }
  TimerId call_at_or_later(SimTime deadline, Micros slack, Task task) override {
    return target_.call_at_or_later(deadline, slack, std::move(task));
  }

 private:
  Executor& target_;
};

TEST(WorldStreamerThreads, EachThreadsSlotsFallBetweenTheOtherThreadsSlots) {
  WorldConfig config = fleet_of(4, false);
  config.control_tick_slots = 2;
  std::optional<ExecutorView> second;   // outlives the World, which keeps its address
  VirtualWorld sim(config);
  second.emplace(sim.executor());
  auto post = [&sim](std::function<void()> task) { sim.executor().post(std::move(task)); };
  sim.world().set_streamer_threads({{&sim.executor(), post}, {&*second, post}}, post);
  ASSERT_TRUE(sim.start());
  std::vector<std::unique_ptr<testing::VehiclePeer>> peers;
  for (int index = 0; index < 4; ++index) peers.push_back(connect_vehicle_peer(sim, vehicle_name(index)));
  sim.run_for(Millis{100});
  // Vehicles 0 and 2 are thread 0's (its slots 0 and 1: 0 and 5 ms), 1 and 3 thread 1's, whose
  // slots come a quarter of the period later (half a slot: 2.5 and 7.5 ms).
  std::vector<std::int64_t> phases;
  for (const auto& peer : peers) {
    ASSERT_GE(peer->received_at.size(), 9u);
    EXPECT_TRUE(cadence_exact(peer->received_at));
    const std::int64_t apart = (peer->received_at.back() - peers.front()->received_at.back()).count();
    phases.push_back((apart % tick.count() + tick.count()) % tick.count());
  }
  EXPECT_EQ(phases, (std::vector<std::int64_t>{0, 2'500, 5'000, 7'500}));
}

TEST(WorldStreamerThreads, LinkMessagesCrossInBatchesBothWays) {
  VirtualWorld sim(fleet_of(6, false));
  SameExecutorThreads::posts = 0;
  SameExecutorThreads threads(sim);
  ASSERT_TRUE(sim.start());
  sim.run_for(Millis{1000});
  for (int index = 0; index < 6; ++index) {
    const std::string name = vehicle_name(index);
    const FaultSet& faults = sim.world().streamer(name).faults();
    // Operator messages arrive (no NoControlMessage); without a vehicle only VehicleNoResponse.
    EXPECT_FALSE(faults.contains(FaultId::NoControlMessage)) << name;
    EXPECT_TRUE(faults.contains(FaultId::VehicleNoResponse)) << name;
  }
  // Feedback and video frames (30 Hz from each Streamer) reach the Player.
  const PlayerStats& player = sim.world().player().stats();
  EXPECT_GE(player.feedback_received, 6u * 29u);
  EXPECT_GE(player.video_frames_received, 6u * 29u);
  // One Player frame to 6 Streamers on 2 threads is 2 posts, not 6: ≈ 2 per 10 ms frame plus
  // the feedback, video and pongs the other way, batched per instant.
  EXPECT_GT(SameExecutorThreads::posts, 100);
  EXPECT_LT(SameExecutorThreads::posts, 600);
}

TEST(WorldStreamerThreads, RefusesInProcessClientsAndThreadsWithoutAPoster) {
  {
    VirtualWorld sim(fleet_of(2, true));
    SameExecutorThreads threads(sim);
    const Status status = sim.start();
    ASSERT_FALSE(status);
    EXPECT_NE(status.error().detail.find("no in-process client"), std::string::npos) << status.error().detail;
  }
  {
    VirtualWorld sim(fleet_of(2, false));
    sim.world().set_streamer_threads({{&sim.executor(), nullptr}}, [](std::function<void()>) {});
    EXPECT_FALSE(sim.start());
  }
}

}  // namespace
}  // namespace ocp::world_test
