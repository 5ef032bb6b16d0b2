// Cameras (CameraLost, missing_cameras, SEI) and the frame loop (feedback, StreamerSlow).
#include <algorithm>
#include <cmath>

#include "streamer_harness.hpp"

namespace ocp::streamer_test {
namespace {

StreamerConfig two_camera_config() {
  StreamerConfig config = test_config();
  config.cameras = {CameraConfig{"front", 30.0, true, 25000},
                    CameraConfig{"rear", 30.0, false, 12000}};
  return config;
}

TEST(StreamerCameras, EachCameraSendsFramesAtItsFps) {
  StreamerConfig config = two_camera_config();
  config.cameras[1].fps = 10.0;
  StreamerHarness harness(config);
  harness.core.start();
  harness.executor.run_until(ms(1000) - Micros{1});
  std::size_t front = 0;
  std::size_t rear = 0;
  for (const auto& [at, frame] : harness.received_of<VideoFrame>()) {
    if (frame.camera == "front") {
      EXPECT_EQ(frame.frame_number, front);
      EXPECT_EQ(frame.size_bytes, 25000u);
      EXPECT_EQ(at, Micros{std::llround(static_cast<double>(front) * 1e6 / 30.0)});
      ++front;
    } else {
      EXPECT_EQ(frame.camera, "rear");
      EXPECT_EQ(at, ms(100 * static_cast<std::int64_t>(rear)));
      ++rear;
    }
  }
  EXPECT_EQ(front, 30u);
  EXPECT_EQ(rear, 10u);
}

TEST(StreamerCameras, CameraLostAfterMoreThan200MsOfAStalledCamera) {
  StreamerHarness harness(two_camera_config());
  TestVehicle& vehicle = harness.connect_vehicle();
  harness.core.start();
  Controller pressed;
  pressed.buttons.x = true;
  harness.schedule_fresh_controls(ms(5), ms(995), pressed);
  // Front frames at 0, 33.333, 66.667, 100 ms; stalled from 110 ms: last frame at 100 ms.
  harness.executor.run_until(ms(110));
  harness.core.set_camera_stalled("front", true);
  harness.executor.run_until(ms(405));
  harness.core.set_camera_stalled("front", false);  // next front frame at 433.333 ms
  harness.executor.run_until(ms(500));

  EXPECT_EQ(harness.observer.changes(FaultId::CameraLost, true), std::vector<SimTime>{ms(310)});
  EXPECT_EQ(harness.observer.changes(FaultId::CameraLost, false), std::vector<SimTime>{ms(440)});
  for (std::size_t k = 0; k < vehicle.received.size(); ++k) {
    const SimTime at = vehicle.received_at[k];
    const auto& telemetry = vehicle.received[k].telemetry;
    if (at >= ms(310) && at < ms(440)) {
      EXPECT_EQ(telemetry.missing_cameras, std::vector<std::string>{"front"}) << at.count();
      EXPECT_TRUE(telemetry.fault);
      EXPECT_EQ(telemetry.fault_reason, "Camera Lost");
      // CameraLost is not a control-path fault: the controller passes through.
      EXPECT_EQ(vehicle.received[k].controller, pressed);
    } else {
      EXPECT_TRUE(telemetry.missing_cameras.empty()) << at.count();
    }
  }
  for (const auto& [at, feedback] : harness.received_of<StreamerFeedback>()) {
    if (at > ms(310) && at < ms(440)) {
      EXPECT_EQ(feedback.missing_cameras, std::vector<std::string>{"front"});
    }
  }
  // No front frame while stalled.
  for (const auto& [at, frame] : harness.received_of<VideoFrame>()) {
    if (frame.camera == "front") {
      EXPECT_FALSE(at > ms(110) && at < ms(433));
    }
  }
}

TEST(StreamerCameras, CameraWithoutDropDetectorNeverRaisesCameraLost) {
  StreamerHarness harness(two_camera_config());
  TestVehicle& vehicle = harness.connect_vehicle();
  harness.core.start();
  harness.core.set_camera_stalled("rear", true);
  harness.executor.run_until(ms(2000));
  EXPECT_FALSE(harness.core.faults().contains(FaultId::CameraLost));
  for (const auto& message : vehicle.received) EXPECT_TRUE(message.telemetry.missing_cameras.empty());
  for (const auto& [at, frame] : harness.received_of<VideoFrame>()) EXPECT_EQ(frame.camera, "front");
}

TEST(StreamerCameras, VideoFramesCarryTheLatestEchoedPairAsSei) {
  StreamerHarness harness;
  TestVehicle& vehicle = harness.connect_vehicle();
  vehicle.echo = true;
  harness.core.start();
  harness.executor.run_until(ms(500));
  const auto frames = harness.received_of<VideoFrame>();
  ASSERT_EQ(frames.size(), 16u);
  EXPECT_FALSE(frames[0].second.sei.has_value());  // 0 ms: nothing echoed yet
  for (std::size_t k = 1; k < frames.size(); ++k) {
    // The newest tick strictly before the frame was echoed at once (a frame due at the same
    // microsecond as a tick was scheduled first, so it runs before that tick).
    const std::int64_t tick_us = (frames[k].first.count() - 1) / 10'000 * 10'000;
    ASSERT_TRUE(frames[k].second.sei.has_value());
    EXPECT_EQ(frames[k].second.sei->ack_time, static_cast<std::uint64_t>(tick_us)) << k;
  }
}

TEST(StreamerFrameLoop, SendsOneFeedbackPerFrameWithVehicleDataAndLastRemoteInput) {
  StreamerHarness harness;
  TestVehicle& vehicle = harness.connect_vehicle();
  harness.core.start();
  harness.schedule_fresh_controls(ms(5), ms(995), Controller{});
  harness.executor.run_until(ms(100));
  VehicleUserData data{Position{57.7, 11.9}, RawJson{R"({"speed":3})"}};
  vehicle.send_response(VehicleResponseMessage{AckPair{1, 2}, data});
  harness.executor.run_until(ms(1000) - Micros{1});

  const auto feedback = harness.received_of<StreamerFeedback>();
  ASSERT_EQ(feedback.size(), 30u);
  for (std::size_t k = 0; k < feedback.size(); ++k) {
    EXPECT_EQ(feedback[k].first, Micros{std::llround(static_cast<double>(k) * 1e6 / 30.0)});
    EXPECT_EQ(feedback[k].second.sequence, k);
  }
  // The frame at 133.333 ms repeats the data that arrived at 100 ms.
  EXPECT_FALSE(feedback[3].second.vehicle_data.has_value());
  EXPECT_EQ(feedback[4].second.vehicle_data, data);
  EXPECT_EQ(feedback[4].second.vehicle_data_age, Micros{33'333});
  EXPECT_EQ(feedback[29].second.vehicle_data, data);
  EXPECT_EQ(feedback[29].second.last_remote_input, Controller{});
  EXPECT_EQ(feedback[29].second.latency_ms, 6u);  // pair of 960 ms at 966.667 ms
  EXPECT_TRUE(feedback[29].second.receiver_faults.empty());
  // The frame loop was started before the control ticker: at 0 ms nothing was sent yet.
  EXPECT_FALSE(feedback[0].second.last_remote_input.has_value());
  EXPECT_EQ(feedback[1].second.last_remote_input, Controller{});
}

TEST(StreamerFrameLoop, FeedbackReportsActiveReceiverFaults) {
  StreamerHarness harness;
  harness.core.start();
  harness.executor.run_until(ms(1100));
  const auto feedback = harness.received_of<StreamerFeedback>();
  ASSERT_FALSE(feedback.empty());
  EXPECT_EQ(feedback.back().second.receiver_faults,
            (std::vector<FaultId>{FaultId::VehicleNoResponse, FaultId::NoControlMessage}));
  EXPECT_FALSE(feedback.back().second.last_remote_input.has_value());
  EXPECT_FALSE(feedback.back().second.latency_ms.has_value());
}

TEST(StreamerFrameLoop, StreamerSlowRaisedByAnOverlongIterationAndClearedByTheNext) {
  StreamerHarness harness;
  harness.core.start();
  harness.executor.run_until(ms(50));
  harness.core.inject_frame_loop_stall(ms(600));
  harness.executor.run_until(ms(800));

  // The iteration due at 66.667 ms is blocked for 600 ms and completes at 666.667 ms; the
  // next one runs at the first deadline after that, 700 ms.
  EXPECT_EQ(harness.observer.changes(FaultId::StreamerSlow, true),
            std::vector<SimTime>{Micros{666'667}});
  EXPECT_EQ(harness.observer.changes(FaultId::StreamerSlow, false), std::vector<SimTime>{ms(700)});
  std::vector<SimTime> times;
  for (const auto& [at, feedback] : harness.received_of<StreamerFeedback>()) times.push_back(at);
  const std::vector<SimTime> expected = {Micros{0},       Micros{33'333}, Micros{666'667},
                                         Micros{700'000}, Micros{733'333}, Micros{766'667},
                                         Micros{800'000}};
  EXPECT_EQ(times, expected);
  const auto feedback = harness.received_of<StreamerFeedback>();
  const auto& slow = feedback[2].second.receiver_faults;
  EXPECT_NE(std::find(slow.begin(), slow.end(), FaultId::StreamerSlow), slow.end());
  const auto& normal = feedback[3].second.receiver_faults;
  EXPECT_EQ(std::find(normal.begin(), normal.end(), FaultId::StreamerSlow), normal.end());
}

TEST(StreamerFrameLoop, StallOfExactlyTheThresholdIsNotSlow) {
  StreamerHarness harness;
  harness.core.start();
  harness.executor.run_until(ms(50));
  harness.core.inject_frame_loop_stall(ms(500));
  harness.executor.run_until(ms(1000));
  EXPECT_TRUE(harness.observer.changes(FaultId::StreamerSlow, true).empty());
  EXPECT_EQ(harness.core.stats().frame_loop_iterations, 16u);  // 0, 33, stall→566, 600…1000
}

TEST(StreamerFrameLoop, PingIsAnsweredAtOnceWithTheSameId) {
  StreamerHarness harness;
  harness.core.start();
  harness.executor.run_until(ms(3));
  harness.core.handle_link_message(Ping{42, ms(2)});
  harness.executor.run_until(ms(3));
  const auto pongs = harness.received_of<Pong>();
  ASSERT_EQ(pongs.size(), 1u);
  EXPECT_EQ(pongs[0].first, ms(3));
  EXPECT_EQ(pongs[0].second.id, 42u);
  EXPECT_EQ(pongs[0].second.ping_sent_at, ms(2));
}

}  // namespace
}  // namespace ocp::streamer_test
