#pragma once
// Simulated cameras (SPEC §5 step 3, §6 CameraLost, §8): each produces frames at its own fps
// on absolute deadlines; a stalled camera keeps its schedule but produces nothing. The drop
// detector of a monitored camera fires when its last frame is older than the drop timeout.
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "ocp/executor.hpp"
#include "ocp/link_messages.hpp"
#include "ocp/log.hpp"
#include "rate_schedule.hpp"
#include "streamer/streamer_core.hpp"

namespace ocp::streamer {

class CameraSet {
 public:
  // Receives each produced frame (camera, frame_number, size filled; the core adds SEI).
  using FrameSink = std::function<void(VideoFrame&&)>;

  CameraSet(Executor& executor, const std::vector<CameraConfig>& cameras, Logger logger);
  ~CameraSet();
  CameraSet(const CameraSet&) = delete;
  CameraSet& operator=(const CameraSet&) = delete;

  void start(SimTime start_time, FrameSink sink);
  void stop();
  // False when no camera has that name.
  bool set_stalled(std::string_view name, bool stalled);

  // Names, in configuration order, of monitored cameras whose newest frame (or start, if
  // none yet) is older than `drop_timeout` at `now`. Fills `out` (cleared first).
  void missing_cameras(SimTime now, Micros drop_timeout, std::vector<std::string>& out) const;

 private:
  struct Camera {
    CameraConfig config;
    RateSchedule schedule{SimTime{0}, 0.0};
    std::uint64_t next_index = 0;
    std::uint64_t frames_produced = 0;
    bool stalled = false;
    SimTime last_frame_at{};
    Executor::TimerId timer = 0;
  };
  void arm(Camera& camera);
  void on_due(Camera& camera);

  Executor& executor_;
  Logger logger_;
  std::vector<Camera> cameras_;
  FrameSink sink_;
  bool running_ = false;
};

}  // namespace ocp::streamer
