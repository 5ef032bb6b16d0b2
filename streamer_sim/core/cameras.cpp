#include "cameras.hpp"

namespace ocp::streamer {

CameraSet::CameraSet(Executor& executor, const std::vector<CameraConfig>& cameras, Logger logger)
    : executor_(executor), logger_(std::move(logger)) {
  cameras_.reserve(cameras.size());
  for (const CameraConfig& config : cameras) cameras_.push_back(Camera{config});
}

CameraSet::~CameraSet() { stop(); }

void CameraSet::start(SimTime start_time, FrameSink sink) {
  stop();
  sink_ = std::move(sink);
  running_ = true;
  for (Camera& camera : cameras_) {
    camera.schedule = RateSchedule(start_time, camera.config.fps);
    camera.next_index = 0;
    camera.last_frame_at = start_time;
    if (!camera.schedule.valid()) {
      logger_.error("camera {}: fps {} is not a positive rate; it will produce no frames",
                    camera.config.name, camera.config.fps);
      continue;
    }
    arm(camera);
  }
}

void CameraSet::stop() {
  running_ = false;
  for (Camera& camera : cameras_) {
    if (camera.timer != 0) executor_.cancel(camera.timer);
    camera.timer = 0;
  }
}

bool CameraSet::set_stalled(std::string_view name, bool stalled) {
  for (Camera& camera : cameras_) {
    if (camera.config.name == name) {
      if (camera.stalled != stalled) {
        logger_.info("camera {}: {}", camera.config.name, stalled ? "stalled" : "resumed");
      }
      camera.stalled = stalled;
      return true;
    }
  }
  return false;
}

void CameraSet::missing_cameras(SimTime now, Micros drop_timeout,
                                std::vector<std::string>& out) const {
  out.clear();
  if (!running_) return;
  for (const Camera& camera : cameras_) {
    if (camera.config.drop_detector && now - camera.last_frame_at > drop_timeout) {
      out.push_back(camera.config.name);
    }
  }
}

void CameraSet::arm(Camera& camera) {
  // Cameras live in a vector that never changes size after construction, so the address is
  // stable for the timer's lifetime.
  Camera* target = &camera;
  camera.timer = executor_.call_at(camera.schedule.deadline(camera.next_index),
                                   [this, target] { on_due(*target); });
}

void CameraSet::on_due(Camera& camera) {
  camera.timer = 0;
  if (!running_) return;
  const SimTime now = executor_.now();
  if (!camera.stalled) {
    camera.last_frame_at = now;
    VideoFrame frame;
    frame.camera = camera.config.name;
    frame.frame_number = camera.frames_produced++;
    frame.size_bytes = camera.config.frame_size_bytes;
    if (sink_) sink_(std::move(frame));
  }
  // Skip deadlines that already passed instead of bunching frames (real-time lateness).
  camera.next_index = camera.schedule.first_index_after(now, camera.next_index + 1);
  arm(camera);
}

}  // namespace ocp::streamer
