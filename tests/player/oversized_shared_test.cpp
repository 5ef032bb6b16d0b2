// Virtual time: a Player serving a fleet whose VehicleOcpShared grows past 16 KiB never sends
// it (SPEC §2) and says so with ONE warning per episode — a run of oversized frames — not one
// per frame (issue 13: at 10 000 vehicles every frame is oversized). When the object fits
// again the episode ends (one info line) and the next episode is warned about again.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "ocp/frame.hpp"
#include "ocp/json_codec.hpp"
#include "player_harness.hpp"

namespace ocp::testing {
namespace {

constexpr int oversized_fleet_size = 10;
constexpr int long_cameras = 3;

// Three cameras with 600-character names per vehicle: while they are lost, every entry names
// them in missing_cameras and the whole object is well over 16 KiB; otherwise it fits.
std::string long_camera(int index) { return "camera-" + std::to_string(index) + "-" + std::string(600, 'x'); }

PlayerConfig oversized_fleet_config() {
  PlayerConfig config;
  config.fleet = true;
  config.client_read_timeout = Micros{0};   // the test's client never writes
  return config;
}

class OversizedSharedTest : public ::testing::Test {
 protected:
  OversizedSharedTest() : harness_(oversized_fleet_config()) {}

  void SetUp() override {
    for (int index = 0; index < oversized_fleet_size; ++index) {
      ASSERT_TRUE(harness_.add_vehicle("vehicle-" + std::to_string(index)).ok());
    }
    harness_.player.start();
    report_feedback();
    PipeEnds pipe = make_pipe(harness_.executor);
    client_end_ = pipe.b;
    client_end_->set_handlers({[this](std::string_view bytes) { bytes_received_ += bytes.size(); },
                               [](const std::string&) {}});
    harness_.player.accept_client_connection(pipe.a);
  }

  // Every vehicle's Streamer reports each 10 ms, naming the cameras it has lost.
  void report_feedback() {
    StreamerFeedback feedback;
    if (long_cameras_lost_) {
      for (int camera = 0; camera < long_cameras; ++camera) feedback.missing_cameras.push_back(long_camera(camera));
    }
    for (const std::string& vehicle : harness_.player.vehicles()) {
      harness_.player.handle_link_message(vehicle, LinkMessage{feedback});
    }
    harness_.executor.call_after(Micros{10'000}, [this] { report_feedback(); });
  }

  void lose_long_cameras(bool lost) { long_cameras_lost_ = lost; }
  void run_for(Micros duration) { harness_.executor.run_for(duration); }

  std::size_t shared_size() {
    std::string json;
    encode_vehicle_ocp_shared(harness_.player.last_shared(), json);
    return json.size();
  }

  int logged(LogLevel level, const std::string& needle) const {
    int count = 0;
    for (const CapturedLog::Line& line : harness_.log.lines()) {
      if (line.message.find(needle) == std::string::npos) continue;
      EXPECT_EQ(line.level, level) << line.message;
      ++count;
    }
    return count;
  }
  int not_sent_warnings() const { return logged(LogLevel::warn, "VehicleOcpShared not sent"); }
  int fits_again_infos() const { return logged(LogLevel::info, "VehicleOcpShared fits again"); }

  const PlayerStats& stats() { return harness_.player.stats(); }

  PlayerHarness harness_;
  bool long_cameras_lost_ = false;
  std::shared_ptr<ByteStream> client_end_;
  std::uint64_t bytes_received_ = 0;
};

TEST_F(OversizedSharedTest, OneWarningPerEpisodeNotPerFrame) {
  run_for(Micros{1'000'000});
  ASSERT_LE(shared_size(), max_payload_bytes) << "the fleet must fit while no camera is lost";
  EXPECT_GT(stats().client_frames_sent, 50u);
  EXPECT_EQ(stats().client_frames_too_large, 0u);

  // Episode 1: every vehicle loses its long-named cameras; the object no longer fits.
  lose_long_cameras(true);
  run_for(Micros{2'000'000});
  ASSERT_GT(shared_size(), max_payload_bytes) << "precondition: lost cameras make it oversized";
  const std::uint64_t dropped_first = stats().client_frames_too_large;
  EXPECT_GT(dropped_first, 50u);   // most of 200 frames
  EXPECT_EQ(not_sent_warnings(), 1);
  const std::uint64_t received_during_episode = bytes_received_;
  run_for(Micros{500'000});
  EXPECT_EQ(bytes_received_, received_during_episode) << "an oversized frame must never be sent";
  EXPECT_EQ(not_sent_warnings(), 1);

  // The cameras come back: frames fit again, the episode ends with one info line.
  lose_long_cameras(false);
  run_for(Micros{2'000'000});
  ASSERT_LE(shared_size(), max_payload_bytes);
  EXPECT_EQ(fits_again_infos(), 1);
  EXPECT_EQ(not_sent_warnings(), 1);
  EXPECT_GT(bytes_received_, received_during_episode);

  // Episode 2 is warned about again, once.
  lose_long_cameras(true);
  run_for(Micros{2'000'000});
  EXPECT_GT(stats().client_frames_too_large, dropped_first);
  EXPECT_EQ(not_sent_warnings(), 2);
  EXPECT_LE(stats().client_frames_sent + stats().client_frames_too_large, stats().frames);
}

}  // namespace
}  // namespace ocp::testing
