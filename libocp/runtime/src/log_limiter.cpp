#include "ocp/log_limiter.hpp"

#include <fmt/format.h>

namespace ocp {

std::string format_span(Micros span) {
  return fmt::format("{:.3g} s", static_cast<double>(span.count()) / 1e6);
}

std::string RepeatedWarning::Summary::text(std::string_view what) const {
  return fmt::format("{} {} in the last {}", count, what, format_span(span));
}

RepeatedWarning::RepeatedWarning(Micros period) : period_(period) {}

void RepeatedWarning::begin(SimTime now) {
  in_episode_ = true;
  counted_since_ = now;
  unlogged_ = 0;
}

bool RepeatedWarning::occurred(SimTime now) {
  ++total_;
  // An episode nobody summarised for a whole period is over (summary() was not called).
  const bool starts = !in_episode_ || now - last_at_ >= period_;
  last_at_ = now;
  if (starts) {
    begin(now);
    return true;
  }
  ++unlogged_;
  return false;
}

void RepeatedWarning::count(SimTime now) {
  ++total_;
  if (!in_episode_ || now - last_at_ >= period_) begin(now);
  last_at_ = now;
  ++unlogged_;
}

std::optional<RepeatedWarning::Summary> RepeatedWarning::summary(SimTime now) {
  if (!in_episode_) return std::nullopt;
  if (now - last_at_ >= period_) {
    // A whole period without one: the episode is over. What it left uncounted is said now.
    in_episode_ = false;
    if (unlogged_ == 0) return std::nullopt;
    return Summary{unlogged_, now - counted_since_, true};
  }
  if (now - counted_since_ < period_ || unlogged_ == 0) return std::nullopt;
  Summary summary{unlogged_, now - counted_since_, false};
  counted_since_ = now;
  unlogged_ = 0;
  return summary;
}

std::optional<RepeatedWarning::Summary> RepeatedWarning::flush(SimTime now) {
  if (!in_episode_) return std::nullopt;
  in_episode_ = false;
  if (unlogged_ == 0) return std::nullopt;
  return Summary{unlogged_, now - counted_since_, true};
}

WarnedNames::WarnedNames(std::size_t capacity, Micros period) : capacity_(capacity), overflow_(period) {}

bool WarnedNames::first_time(std::string_view name, SimTime now) {
  if (contains(name)) return false;
  if (names_.size() < capacity_) {
    names_.emplace(name);
    return true;
  }
  overflow_.count(now);
  return false;
}

ConnectionLogBudget::ConnectionLogBudget(std::size_t lines_per_period, Micros period)
    : lines_per_period_(lines_per_period), period_(period) {}

bool ConnectionLogBudget::admit(const Logger& logger, SimTime now) {
  if (now - window_start_ >= period_) {
    window_start_ = now;
    written_in_window_ = 0;
  }
  if (written_in_window_ >= lines_per_period_) {
    if (suppressed_ == 0) suppressed_since_ = now;
    ++suppressed_;
    ++suppressed_total_;
    return false;
  }
  ++written_in_window_;
  if (suppressed_ > 0) {
    logger.warn("{} connection lines not written in the last {} (a connection storm?)", suppressed_,
                format_span(now - suppressed_since_));
    suppressed_ = 0;
  }
  return true;
}

}  // namespace ocp
