#pragma once
// What a case body sees: the Streamer host (already listening, with a fresh Streamer), the
// wire log of this case, and bounded waits. Every wait is cut at the case deadline: past it,
// CaseTimeout is thrown and the runner turns it into a FAILED verdict — a case can never hang.
#include <chrono>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "conformance/control_frames.hpp"
#include "conformance/streamer_host.hpp"
#include "conformance/wire_log.hpp"

namespace ocp::conformance {

struct CaseTimeout : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class CaseContext {
 public:
  // `deadline_us` is on the host's clock (now_us()): wall time, or virtual time.
  CaseContext(StreamerHost& host, WireLog& log, std::int64_t deadline_us, double timeout_scale);

  StreamerHost& host() { return host_; }
  // The client's interlock buttons (RunOptions::interlock), for the §10 cases' scripts.
  const InterlockButtons& interlock() const { return interlock_; }
  void set_interlock(InterlockButtons interlock) { interlock_ = std::move(interlock); }
  StreamerCore& streamer() { return host_.streamer(); }
  WireLog& log() { return log_; }
  const std::vector<WireLogEntry>& entries() const { return log_.entries(); }
  std::int64_t now_us() const { return host_.now_us(); }
  // The case runs in virtual time (ocp_conformance --time virtual): every wait is exact, so a
  // bound needs no slack for the machine's load.
  bool virtual_time() { return host_.controller() != nullptr; }
  void note(std::string text) { log_.note(now_us(), std::move(text)); }

  // Observation window: runs the Streamer for `duration` (not scaled: it is what we watch).
  void run_for(std::chrono::milliseconds duration);
  // Waits for `done` at most `timeout` × timeout_scale (and never past the case deadline).
  bool wait_until(const std::function<bool()>& done, std::chrono::milliseconds timeout);
  // Waits for a client connection to the current Streamer.
  bool wait_connected(std::chrono::milliseconds timeout = std::chrono::milliseconds(10'000));
  // Restarts the Streamer (StreamerHost::restart) and moves the wire log to the new one.
  void restart_streamer(const StreamerSetup& setup);

 private:
  void check_deadline() const;
  StreamerHost& host_;
  WireLog& log_;
  std::int64_t deadline_us_;
  double timeout_scale_;
  InterlockButtons interlock_;
};

}  // namespace ocp::conformance
