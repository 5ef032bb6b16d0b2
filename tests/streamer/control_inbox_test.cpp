// ControlThreadChannelSlow (SPEC §6): the internal control queue backing up.
#include "streamer_harness.hpp"

namespace ocp::streamer_test {
namespace {

TEST(StreamerControlInbox, ControlThreadChannelSlowWhenOldestQueuedMessageIsOlderThan100Ms) {
  StreamerHarness harness;
  TestVehicle& vehicle = harness.connect_vehicle();
  harness.core.start();
  Controller pressed;
  pressed.buttons.b = true;
  harness.schedule_fresh_controls(ms(5), ms(995), pressed);
  harness.core.set_control_thread_stalled(true);
  harness.executor.run_until(ms(150));
  // Oldest queued at 5 ms: the message at 105 ms sees exactly 100 ms (not >), the tick at
  // 110 ms sees 105 ms.
  EXPECT_EQ(harness.observer.changes(FaultId::ControlThreadChannelSlow, true),
            std::vector<SimTime>{ms(110)});
  harness.core.set_control_thread_stalled(false);
  EXPECT_FALSE(harness.core.faults().contains(FaultId::ControlThreadChannelSlow));
  EXPECT_EQ(harness.observer.changes(FaultId::ControlThreadChannelSlow, false),
            std::vector<SimTime>{ms(150)});
  harness.executor.run_until(ms(160));
  // Nothing was applied while stalled (default controller), the backlog is applied after.
  for (std::size_t k = 0; k < vehicle.received.size(); ++k) {
    if (vehicle.received_at[k] <= ms(150)) {
      EXPECT_EQ(vehicle.received[k].controller, Controller::safe_default());
    }
  }
  EXPECT_EQ(vehicle.received.back().controller, pressed);
  EXPECT_FALSE(vehicle.received.back().telemetry.fault);
}

TEST(StreamerControlInbox, ControlThreadChannelSlowWhenBacklogExceedsTheLimit) {
  StreamerConfig config = test_config();
  config.control_queue_limit = 20;
  config.control_queue_max_age = ms(10'000);
  StreamerHarness harness(config);
  harness.core.start();
  harness.core.set_control_thread_stalled(true);
  for (int i = 0; i < 20; ++i) {
    harness.send_control(harness.control_returning(harness.pair_issued_at(ms(0))));
  }
  EXPECT_FALSE(harness.core.faults().contains(FaultId::ControlThreadChannelSlow));
  harness.send_control(harness.control_returning(harness.pair_issued_at(ms(0))));
  EXPECT_TRUE(harness.core.faults().contains(FaultId::ControlThreadChannelSlow));
  EXPECT_TRUE(harness.logged("fault raised: Control Thread Channel Slow"));
}

TEST(StreamerControlInbox, StalledInboxStaysBounded) {
  StreamerHarness harness;
  harness.core.start();
  harness.core.set_control_thread_stalled(true);
  for (int i = 0; i < 10'000; ++i) {
    harness.send_control(harness.control_returning(std::nullopt));
  }
  EXPECT_EQ(harness.core.stats().operator_messages_received, 10'000u);
  EXPECT_TRUE(harness.logged("control inbox full"));
  harness.core.set_control_thread_stalled(false);
  // Only the bounded backlog was applied: each applied message counts one invalid pair.
  EXPECT_EQ(harness.core.stats().invalid_returned_pairs, 4096u);
}

}  // namespace
}  // namespace ocp::streamer_test
