#pragma once
// Keeps a flapping on/off condition from flooding the log. Pure: it reads no clock, every
// call takes `now`, so it is tested in virtual time.
//
// Every edge is logged as usual until the condition is raised `raises_to_flap` times within
// `window`. From then on the edges themselves are not logged; one summary is, at once:
//   "HighLatency flapping: raised 42× in the last 5 s, active 61 % of the time"
// and the log stays quiet until the pattern changes: a new summary when the raise rate
// changes by `rate_change_factor` or the active share by `share_change_points` (looked at
// on an edge, at most once per window); and one line when the condition has not changed for a whole window
// ("HighLatency stopped flapping: active now; raised 85× while flapping"), after which edges
// are logged one by one again. The same line ends it when an edge finds fewer than
// `raises_to_flap` raises in the window (on_steady was not called for a while: a fault raised
// once is never summarised as "flapping"). A share that is neither 0 nor 100 % is never shown
// as such ("<1 %", ">99 %"). Only the log is limited: callers still act on every edge.
//
//   FlapSummariser flaps("HighLatency");
//   on an edge:      if (auto v = flaps.on_edge(active, now); v.log_edge) log the edge;
//                    if (v.summary) log *v.summary;
//   between edges:   if (auto line = flaps.on_steady(now)) log *line;
#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>

#include "ocp/time.hpp"

namespace ocp {

class FlapSummariser {
 public:
  struct Options {
    Micros window{5'000'000};
    std::size_t raises_to_flap = 4;
    double rate_change_factor = 3.0;
    double share_change_points = 25.0;
  };
  struct Verdict {
    bool log_edge = true;                // log this edge as usual
    std::optional<std::string> summary;  // and/or this line
  };

  explicit FlapSummariser(std::string name);
  FlapSummariser(std::string name, Options options);

  [[nodiscard]] Verdict on_edge(bool active, SimTime now);
  // Call whenever the condition is evaluated without changing (or at least once a window).
  [[nodiscard]] std::optional<std::string> on_steady(SimTime now);
  bool flapping() const { return flapping_; }

 private:
  struct Edge {
    SimTime time;
    bool active;
  };
  struct Pattern {
    std::size_t raises = 0;
    Micros span{0};
    double active_share = 0.0;  // 0..1
    double raise_rate() const;  // raises per second over span
  };
  void forget_before(SimTime cutoff);
  Pattern pattern(SimTime now) const;
  Verdict resummarise(SimTime now, bool active);
  std::string summary_text(const Pattern& pattern) const;
  std::string stopped_text(bool active_now) const;

  std::string name_;
  Options options_;
  std::deque<Edge> edges_;         // within the window, oldest first
  bool active_before_edges_ = false;  // the state before edges_.front()
  std::optional<SimTime> first_edge_at_;
  bool flapping_ = false;
  Pattern logged_;                 // the pattern of the last summary
  SimTime checked_at_{0};         // when the pattern was last compared with logged_
  std::uint64_t raises_while_flapping_ = 0;
};

}  // namespace ocp
