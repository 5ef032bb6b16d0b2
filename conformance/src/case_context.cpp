#include "conformance/case_context.hpp"

#include <algorithm>

namespace ocp::conformance {

CaseContext::CaseContext(StreamerHost& host, WireLog& log, std::chrono::steady_clock::time_point deadline,
                         double timeout_scale)
    : host_(host), log_(log), deadline_(deadline), timeout_scale_(timeout_scale) {}

void CaseContext::check_deadline() const {
  if (std::chrono::steady_clock::now() >= deadline_) throw CaseTimeout("case timed out");
}

void CaseContext::run_for(std::chrono::milliseconds duration) {
  const auto until = std::min(std::chrono::steady_clock::now() + duration, deadline_);
  host_.run_until([&] { return std::chrono::steady_clock::now() >= until; }, duration + std::chrono::milliseconds(1));
  check_deadline();
}

bool CaseContext::wait_until(const std::function<bool()>& done, std::chrono::milliseconds timeout) {
  const auto scaled =
      std::chrono::milliseconds(static_cast<std::int64_t>(static_cast<double>(timeout.count()) * timeout_scale_));
  const auto now = std::chrono::steady_clock::now();
  const auto limit = std::min(now + scaled, deadline_);
  const bool ok = host_.run_until(done, std::chrono::duration_cast<std::chrono::milliseconds>(limit - now));
  if (!ok) check_deadline();
  return ok;
}

bool CaseContext::wait_connected(std::chrono::milliseconds timeout) {
  return wait_until([&] { return host_.client_connected(); }, timeout);
}

void CaseContext::restart_streamer(const StreamerSetup& setup) {
  note("Streamer restart: connection closed, listening socket reopened, new MAC key");
  host_.stop_streamer();  // still attached: the close is in the log
  log_.detach();
  if (auto status = host_.restart(setup); !status) {
    throw std::runtime_error("restart failed: " + status.error().message());
  }
  log_.attach(host_.client_events(), setup.operator_side ? Wire::operator_ : Wire::vehicle);
}

}  // namespace ocp::conformance
