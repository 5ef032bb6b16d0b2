#include "conformance/case_context.hpp"

#include <algorithm>

namespace ocp::conformance {

namespace {

// Rounded up: a wait cut at the deadline reaches it, so the next check throws CaseTimeout.
std::chrono::milliseconds ms_of(std::int64_t us) { return std::chrono::milliseconds(std::max<std::int64_t>(0, (us + 999) / 1000)); }

}  // namespace

CaseContext::CaseContext(StreamerHost& host, WireLog& log, std::int64_t deadline_us, double timeout_scale)
    : host_(host), log_(log), deadline_us_(deadline_us), timeout_scale_(timeout_scale) {}

void CaseContext::check_deadline() const {
  if (host_.now_us() >= deadline_us_) throw CaseTimeout("case timed out");
}

void CaseContext::run_for(std::chrono::milliseconds duration) {
  const std::int64_t left_us = deadline_us_ - host_.now_us();
  host_.run_for(std::min(duration, ms_of(left_us)));
  check_deadline();
}

bool CaseContext::wait_until(const std::function<bool()>& done, std::chrono::milliseconds timeout) {
  const auto scaled =
      std::chrono::milliseconds(static_cast<std::int64_t>(static_cast<double>(timeout.count()) * timeout_scale_));
  const bool ok = host_.run_until(done, std::min(scaled, ms_of(deadline_us_ - host_.now_us())));
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
