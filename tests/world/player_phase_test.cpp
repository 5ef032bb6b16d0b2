// WorldConfig::player_phase: the Player's frames fall that long after the Streamers' control
// ticks (real-time benchmarks use it so the simulated operator does not run inside the
// vehicle's round trip), the loop still closes, and a negative phase is refused.
#include <gtest/gtest.h>

#include <variant>
#include <vector>

#include "world_fixture.hpp"

namespace ocp::world_test {
namespace {

struct Phases {
  std::vector<SimTime> operator_sends;   // the Player's OperatorControl onto the link
  std::vector<SimTime> control_frames;   // the Streamer's control frames to the vehicle
};

Phases run_with_phase(Micros phase) {
  WorldConfig config = one_vehicle_config();
  config.player_phase = phase;
  VirtualWorld sim(config);
  Phases seen;
  auto subscription = sim.world().events().subscribe([&seen](const Event& event) {
    if (const auto* link = std::get_if<LinkEvent>(&event.body)) {
      if (link->kind == LinkMessageKind::operator_control && link->outcome == LinkOutcome::sent) {
        seen.operator_sends.push_back(event.time);
      }
    } else if (const auto* frame = std::get_if<WireFrame>(&event.body)) {
      if (frame->wire == Wire::vehicle && frame->direction == FrameDirection::out) {
        seen.control_frames.push_back(event.time);
      }
    }
  });
  EXPECT_TRUE(sim.start());
  sim.run_for(Millis{500});
  EXPECT_TRUE(sim.world().streamer("truck-1").latency_ms().has_value()) << "the loop did not close";
  return seen;
}

TEST(WorldPlayerPhase, OperatorFramesFallThePhaseAfterTheControlTicks) {
  const Micros phase{1'250};
  const Phases seen = run_with_phase(phase);
  ASSERT_GT(seen.operator_sends.size(), 40u);
  ASSERT_GT(seen.control_frames.size(), 40u);
  EXPECT_EQ(seen.operator_sends.front(), SimTime{phase});
  for (const SimTime at : seen.operator_sends) EXPECT_EQ(at % tick, phase) << at.count();
  for (const SimTime at : seen.control_frames) EXPECT_EQ(at % tick, Micros{0}) << at.count();
}

TEST(WorldPlayerPhase, ZeroKeepsTheOperatorOnTheTick) {
  const Phases seen = run_with_phase(Micros{0});
  ASSERT_GT(seen.operator_sends.size(), 40u);
  for (const SimTime at : seen.operator_sends) EXPECT_EQ(at % tick, Micros{0}) << at.count();
}

TEST(WorldPlayerPhase, NegativePhaseIsAConfigurationError) {
  WorldConfig config = one_vehicle_config();
  config.player_phase = Micros{-1};
  VirtualWorld sim(config);
  const Status started = sim.start();
  ASSERT_FALSE(started);
  EXPECT_NE(started.error().detail.find("player_phase"), std::string::npos) << started.error().detail;
}

}  // namespace
}  // namespace ocp::world_test
