#pragma once
// Log-once-then-summarise for what a web view client sends that we drop (docs/webview.md):
// the first drop of each kind is a warning with the details, later ones are only counted and
// reported as one summary line at most every `summary_period`, and once more at close — a
// page stuck in a loop can never flood the log.
#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "ocp/executor.hpp"
#include "ocp/log.hpp"

namespace ocp::webview {

enum class DropKind { malformed, unknown_name, oversized, binary, flood };
inline constexpr std::size_t drop_kind_count = 5;
std::string_view drop_kind_name(DropKind kind);   // "malformed", "unknown name", …

class DropLog {
 public:
  DropLog(Logger logger, std::string peer, Micros summary_period = Micros{10'000'000});

  // Counts one drop. Returns true when it was the first of its kind on this connection (it
  // has been logged with `detail`; the caller may also tell the page).
  bool dropped(DropKind kind, SimTime now, std::string_view detail);
  // Logs what was counted but not reported yet (call when the connection closes).
  void flush();

  std::uint64_t total(DropKind kind) const { return totals_[static_cast<std::size_t>(kind)]; }

 private:
  void summarise(SimTime now);

  Logger logger_;
  std::string peer_;
  Micros summary_period_;
  std::array<std::uint64_t, drop_kind_count> totals_{};
  std::array<std::uint64_t, drop_kind_count> unreported_{};
  SimTime last_summary_{0};
};

// A token bucket: `rate_per_s` messages a second on average, bursts up to `burst`.
class RateLimiter {
 public:
  RateLimiter(double rate_per_s, double burst) : rate_per_us_(rate_per_s / 1e6), burst_(burst), tokens_(burst) {}
  bool admit(SimTime now) {
    const double elapsed_us = static_cast<double>((now - last_).count());
    last_ = now;
    tokens_ = std::min(burst_, tokens_ + elapsed_us * rate_per_us_);
    if (tokens_ < 1.0) return false;
    tokens_ -= 1.0;
    return true;
  }

 private:
  double rate_per_us_;
  double burst_;
  double tokens_;
  SimTime last_{0};
};

}  // namespace ocp::webview
