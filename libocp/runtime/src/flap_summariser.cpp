#include "ocp/flap_summariser.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include <fmt/format.h>

namespace ocp {

FlapSummariser::FlapSummariser(std::string name) : FlapSummariser(std::move(name), Options{}) {}

FlapSummariser::FlapSummariser(std::string name, Options options)
    : name_(std::move(name)), options_(options) {}

double FlapSummariser::Pattern::raise_rate() const {
  const double seconds = std::max(1e-3, static_cast<double>(span.count()) / 1e6);
  return static_cast<double>(raises) / seconds;
}

void FlapSummariser::forget_before(SimTime cutoff) {
  while (!edges_.empty() && edges_.front().time < cutoff) {
    active_before_edges_ = edges_.front().active;
    edges_.pop_front();
  }
}

FlapSummariser::Pattern FlapSummariser::pattern(SimTime now) const {
  Pattern result;
  // The window, or less when the condition has not been watched that long.
  SimTime from = now - options_.window;
  if (first_edge_at_ && *first_edge_at_ > from) from = *first_edge_at_;
  result.span = now - from;
  Micros active_time{0};
  bool active = active_before_edges_;
  SimTime since = from;
  for (const Edge& edge : edges_) {
    if (edge.active) ++result.raises;
    if (active) active_time += edge.time - since;
    active = edge.active;
    since = edge.time;
  }
  if (active) active_time += now - since;
  if (result.span.count() > 0) {
    result.active_share = static_cast<double>(active_time.count()) / static_cast<double>(result.span.count());
  }
  return result;
}

namespace {

// A share that rounds to 0 % or 100 % but is neither says so: "<1 %", ">99 %".
std::string percent_text(double share) {
  const double percent = share * 100.0;
  if (percent > 0.0 && percent < 0.5) return "<1 %";
  if (percent < 100.0 && percent >= 99.5) return ">99 %";
  return fmt::format("{:.0f} %", percent);
}

}  // namespace

std::string FlapSummariser::summary_text(const Pattern& pattern) const {
  return fmt::format("{} flapping: raised {}× in the last {:.2g} s, active {} of the time", name_,
                     pattern.raises, static_cast<double>(pattern.span.count()) / 1e6,
                     percent_text(pattern.active_share));
}

std::string FlapSummariser::stopped_text(bool active_now) const {
  return fmt::format("{} stopped flapping: {} now; raised {}× while flapping", name_,
                     active_now ? "active" : "cleared", raises_while_flapping_);
}

FlapSummariser::Verdict FlapSummariser::on_edge(bool active, SimTime now) {
  if (!first_edge_at_) first_edge_at_ = now;
  edges_.push_back(Edge{now, active});
  forget_before(now - options_.window);
  if (flapping_) {
    Verdict verdict = resummarise(now, active);
    if (flapping_ && active) ++raises_while_flapping_;   // not the raise that ended it
    return verdict;
  }
  const Pattern current = pattern(now);
  if (current.raises < options_.raises_to_flap) return Verdict{true, std::nullopt};
  flapping_ = true;
  raises_while_flapping_ = current.raises;
  logged_ = current;
  checked_at_ = now;
  return Verdict{false, summary_text(current)};
}

FlapSummariser::Verdict FlapSummariser::resummarise(SimTime now, bool active) {
  // Looked at once per window, and only while edges keep coming: a pattern that is dying
  // out is reported by on_steady's "stopped flapping" line instead.
  if (now - checked_at_ < options_.window) return Verdict{false, std::nullopt};
  checked_at_ = now;
  const Pattern current = pattern(now);
  if (current.raises < options_.raises_to_flap) {
    // Too few raises left in the window to call it flapping (a fault raised once is not
    // flapping; this happens when nobody called on_steady for a while, e.g. the process was
    // stopped): the flapping ends here, and this edge is logged as usual.
    flapping_ = false;
    return Verdict{true, stopped_text(active)};
  }
  const double ratio = (current.raise_rate() + 1e-9) / (logged_.raise_rate() + 1e-9);
  const bool rate_changed = ratio >= options_.rate_change_factor || ratio <= 1.0 / options_.rate_change_factor;
  const bool share_changed =
      std::abs(current.active_share - logged_.active_share) * 100.0 >= options_.share_change_points;
  if (!rate_changed && !share_changed) return Verdict{false, std::nullopt};
  logged_ = current;
  return Verdict{false, summary_text(current)};
}

std::optional<std::string> FlapSummariser::on_steady(SimTime now) {
  if (!flapping_) return std::nullopt;
  if (!edges_.empty() && now - edges_.back().time < options_.window) return std::nullopt;
  forget_before(now - options_.window);
  flapping_ = false;
  return stopped_text(edges_.empty() ? active_before_edges_ : edges_.back().active);
}

}  // namespace ocp
