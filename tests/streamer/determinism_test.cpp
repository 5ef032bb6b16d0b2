// Same inputs → the identical sequence of control frames, byte for byte.
#include "streamer_harness.hpp"

namespace ocp::streamer_test {
namespace {

std::vector<std::string> run_world() {
  StreamerConfig config = test_config();
  config.cameras = {CameraConfig{"front"}, CameraConfig{"rear", 15.0}};
  StreamerHarness harness(config);
  TestVehicle& vehicle = harness.connect_vehicle();
  vehicle.echo = true;
  vehicle.echo_user_data = VehicleUserData{Position{57.7, 11.9}, RawJson{"[1,2,3]"}};
  harness.core.start();
  harness.schedule_controls(ms(3), ms(2997), Micros{20'000}, [&harness](SimTime now) {
    std::optional<AckPair> sei;
    for (const auto& [at, frame] : harness.received_of<VideoFrame>()) {
      if (frame.sei) sei = frame.sei;
    }
    Controller controller;
    controller.axes.left_x = static_cast<double>(now.count() % 1000) / 1000.0;
    OperatorControl control = harness.control_returning(sei, controller);
    control.client_user_data = RawJson{"{\"t\":" + std::to_string(now.count()) + "}"};
    return control;
  });
  harness.executor.run_until(ms(1200));
  harness.core.set_camera_stalled("rear", true);
  harness.executor.run_until(ms(3000));
  return vehicle.raw_payloads;
}

TEST(StreamerDeterminism, SameInputsGiveIdenticalControlFrames) {
  const auto first = run_world();
  const auto second = run_world();
  ASSERT_EQ(first.size(), 301u);
  EXPECT_EQ(first, second);
}

}  // namespace
}  // namespace ocp::streamer_test
