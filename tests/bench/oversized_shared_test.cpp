// Virtual time: a Player serving a fleet whose VehicleOcpShared grows past 16 KiB never sends
// it (SPEC §2) and says so with ONE warning per episode — a run of oversized frames — not one
// per frame (issue 13: at 10 000 vehicles every frame is oversized). When the object fits
// again the episode ends (one info line) and the next episode is warned about again.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "ocp/frame.hpp"
#include "ocp/json_codec.hpp"
#include "ocp/pipe.hpp"
#include "ocp/virtual_executor.hpp"
#include "world/world.hpp"

namespace ocp {
namespace {

constexpr int vehicle_count = 10;
constexpr int long_cameras = 3;

// Three cameras with 300-character names per vehicle: while they are lost, every entry names
// them in missing_cameras and the whole object is well over 16 KiB; otherwise it fits.
std::string long_camera(int index) { return "camera-" + std::to_string(index) + "-" + std::string(300, 'x'); }

WorldConfig fleet_config() {
  WorldConfig config;
  config.seed = 13;
  config.deterministic_keys = true;
  config.player.fleet = true;
  config.player.client_read_timeout = Micros{0};   // the test's client never writes
  for (int index = 0; index < vehicle_count; ++index) {
    VehicleSpec vehicle;
    vehicle.name = "vehicle-" + std::to_string(index);
    vehicle.streamer.cameras = {CameraConfig{"front", 30.0}};
    for (int camera = 0; camera < long_cameras; ++camera) vehicle.streamer.cameras.push_back({long_camera(camera), 30.0});
    config.vehicles.push_back(vehicle);
  }
  return config;
}

struct LogCounts {
  int not_sent_warnings = 0;
  int fits_again_infos = 0;
};

class OversizedSharedTest : public ::testing::Test {
 protected:
  OversizedSharedTest()
      : world_(executor_, fleet_config(), [this](const LogRecord& record) {
          if (record.message.find("VehicleOcpShared not sent") != std::string_view::npos) {
            EXPECT_EQ(record.level, LogLevel::warn);
            ++log_.not_sent_warnings;
          }
          if (record.message.find("VehicleOcpShared fits again") != std::string_view::npos) ++log_.fits_again_infos;
        }) {}

  void SetUp() override {
    ASSERT_TRUE(world_.start().ok());
    PipeEnds pipe = make_pipe(executor_);
    client_end_ = pipe.b;
    client_end_->set_handlers({[this](std::string_view bytes) { bytes_received_ += bytes.size(); },
                               [](const std::string&) {}});
    world_.player().accept_client_connection(pipe.a);
  }

  void stall_long_cameras(bool stalled) {
    for (const std::string& vehicle : world_.vehicles()) {
      for (int camera = 0; camera < long_cameras; ++camera) world_.streamer(vehicle).set_camera_stalled(long_camera(camera), stalled);
    }
  }

  std::size_t shared_size() {
    std::string json;
    encode_vehicle_ocp_shared(world_.player().last_shared(), json);
    return json.size();
  }

  const PlayerStats& stats() { return world_.player().stats(); }

  VirtualExecutor executor_;
  LogCounts log_;
  World world_;
  std::shared_ptr<ByteStream> client_end_;
  std::uint64_t bytes_received_ = 0;
};

TEST_F(OversizedSharedTest, OneWarningPerEpisodeNotPerFrame) {
  executor_.run_for(Micros{1'000'000});
  ASSERT_LE(shared_size(), max_payload_bytes) << "the fleet must fit while no camera is lost";
  EXPECT_GT(stats().client_frames_sent, 50u);
  EXPECT_EQ(stats().client_frames_too_large, 0u);

  // Episode 1: every vehicle loses its long-named cameras; the object no longer fits.
  stall_long_cameras(true);
  executor_.run_for(Micros{2'000'000});
  ASSERT_GT(shared_size(), max_payload_bytes) << "precondition: lost cameras make it oversized";
  const std::uint64_t dropped_first = stats().client_frames_too_large;
  EXPECT_GT(dropped_first, 50u);   // most of 200 frames
  EXPECT_EQ(log_.not_sent_warnings, 1);
  const std::uint64_t received_during_episode = bytes_received_;
  executor_.run_for(Micros{500'000});
  EXPECT_EQ(bytes_received_, received_during_episode) << "an oversized frame must never be sent";
  EXPECT_EQ(log_.not_sent_warnings, 1);

  // The cameras come back: frames fit again, the episode ends with one info line.
  stall_long_cameras(false);
  executor_.run_for(Micros{2'000'000});
  ASSERT_LE(shared_size(), max_payload_bytes);
  EXPECT_EQ(log_.fits_again_infos, 1);
  EXPECT_EQ(log_.not_sent_warnings, 1);
  EXPECT_GT(bytes_received_, received_during_episode);

  // Episode 2 is warned about again, once.
  stall_long_cameras(true);
  executor_.run_for(Micros{2'000'000});
  EXPECT_GT(stats().client_frames_too_large, dropped_first);
  EXPECT_EQ(log_.not_sent_warnings, 2);
  EXPECT_LE(stats().client_frames_sent + stats().client_frames_too_large, stats().frames);
}

}  // namespace
}  // namespace ocp
