// ocp_campaign's memory over a long world (issue #36): a 1 h world with its determinism check
// took 1.18 GB (both runs' traces were kept whole to compare their digests). The digest is
// all the check needs, and the scenario engine's series are bounded, so a world 8 times as
// long needs no more than a few MB more.
#include <gtest/gtest.h>

#include <string>

#include "peak_rss.hpp"
#include "scratch_dir.hpp"

namespace ocp::campaign {
namespace {

using testing_support::memory_is_measurable;
using testing_support::run_measuring_memory;
using testing_support::ScratchDir;

// The calm profile with a fixed duration, one vehicle, no episodes, and every world's
// determinism checked (two runs, the trace on).
std::string long_world_profile(const std::string& duration) {
  return "description: one long calm world\nduration: [" + duration + ", " + duration +
         "]\nvehicles: [1, 1]\nmonitor_share: 0.0\ncameras: [1, 1]\ncamera_fps: [30, 30]\n"
         "link:\n  delay: [10ms, 20ms]\n  jitter: [0ms, 3ms]\n  loss: [0, 0.005]\n"
         "timeline:\n  events: [0, 0]\n  episode: [200ms, 2s]\n  delay: [0ms, 50ms]\n  jitter: [0ms, 10ms]\n"
         "  loss: [0, 0.02]\n  duplicate: [0, 0.01]\n  reorder: [0, 0.01]\n  reorder_extra_delay: [0ms, 10ms]\n"
         "  bandwidth_bps: [1000000, 5000000]\n  queue_limit_bytes: [100000, 400000]\n"
         "weights:\n  impair: 1\n  latency_ramp: 0\n  outage: 0\n  burst_loss: 0\n  camera_stall: 0\n"
         "  frame_loop_stall: 0\n  control_thread_stall: 0\n  disconnect: 0\n  misbehave: 0\n  gamepad_unplug: 0\n"
         "  client_data: 0\n  select_vehicle: 0\n  operator_misbehave: 0\ndeterminism_share: 1.0\n";
}

TEST(CampaignLongWorld, ALongWorldNeedsNoMoreMemoryThanAShortOne) {
  if (!memory_is_measurable()) GTEST_SKIP() << "resident memory means nothing under AddressSanitizer";
  ScratchDir scratch("ocp_campaign_long_world");
  const auto peak_kib = [&](const std::string& duration) {
    const std::string file = scratch.write("profile-" + duration + ".yaml", long_world_profile(duration)).string();
    const auto measured = run_measuring_memory({OCP_CAMPAIGN_PATH, "run", "--profile", file, "--worlds", "1", "--seed", "3",
                                                "-q", "--out", (scratch / ("out-" + duration)).string()});
    EXPECT_EQ(measured.exit_code, 0) << duration;
    return measured.peak_rss_kib;
  };
  const long short_kib = peak_kib("1min");
  const long long_kib = peak_kib("8min");
  EXPECT_LT(long_kib - short_kib, 8 * 1024) << short_kib << " KiB for 1 min, " << long_kib << " KiB for 8 min";
}

}  // namespace
}  // namespace ocp::campaign
