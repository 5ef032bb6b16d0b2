#pragma once
// Keeps what a peer can repeat at will from flooding the log or growing memory. Pure: no
// clock is read, every call takes `now`, so both are tested in virtual time.
// (A condition that turns on and off is FlapSummariser's, flap_summariser.hpp.)
//
// RepeatedWarning — "say it once, then summarise". The first occurrence of an episode is
// logged in full; the next ones are only counted, and summarised at most once a `period`
// while they go on, and once more when a whole period passes without one (the episode has
// ended; the next occurrence is logged in full again):
//
//   RepeatedWarning dropped(Micros{5'000'000});
//   on each occurrence:  if (dropped.occurred(now)) logger.warn("… the full story …");
//   every tick (at least once a period):
//     if (auto s = dropped.summary(now)) logger.warn("… {}", s->text("times"));
//        → "… 500 times in the last 5 s"
//
// WarnedNames — the names already warned about ("unknown vehicle 'x'"), so that one repeated
// at 100 Hz is warned about once, at most `capacity` of them: past that, new names are not
// remembered but counted, and summarised as above ("… and 1 200 more in the last 5 s"). A
// peer sending ever-new names costs at most `capacity` strings and one line a period.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <string_view>

#include "ocp/log.hpp"
#include "ocp/time.hpp"

namespace ocp {

// "5 s", "0.25 s", "1.5 s" (at most three significant digits).
std::string format_span(Micros span);

class RepeatedWarning {
 public:
  struct Summary {
    std::uint64_t count = 0;   // occurrences not logged in full during `span`
    Micros span{0};            // since the episode began or the previous summary
    bool episode_ended = false;
    // "<count> <what> in the last <span>", e.g. "100 times in the last 1 s".
    std::string text(std::string_view what) const;
  };

  explicit RepeatedWarning(Micros period = default_period);

  // One occurrence. True: the first of an episode — log it in full (it is not counted).
  [[nodiscard]] bool occurred(SimTime now);
  // One occurrence that is never logged in full, only counted (WarnedNames' overflow).
  void count(SimTime now);
  // The summary due at `now`, if any. Call it at least once a period while in an episode
  // (or before each occurrence, when there is no tick, and flush() at the end).
  [[nodiscard]] std::optional<Summary> summary(SimTime now);
  // Whatever is counted and not said yet, now, period or not (the source goes away); the
  // episode ends.
  [[nodiscard]] std::optional<Summary> flush(SimTime now);

  bool in_episode() const { return in_episode_; }
  std::uint64_t total() const { return total_; }   // every occurrence ever, logged or not
  Micros period() const { return period_; }

  static constexpr Micros default_period{5'000'000};

 private:
  void begin(SimTime now);

  Micros period_;
  bool in_episode_ = false;
  SimTime last_at_{0};        // the latest occurrence
  SimTime counted_since_{0};  // start of the span the next summary covers
  std::uint64_t unlogged_ = 0;
  std::uint64_t total_ = 0;
};

class WarnedNames {
 public:
  static constexpr std::size_t default_capacity = 64;

  explicit WarnedNames(std::size_t capacity = default_capacity,
                       Micros period = RepeatedWarning::default_period);

  // True: warn about `name` in full now (first time, and there is room to remember it).
  // False: already warned about, or the set is full and it was counted for the summary.
  [[nodiscard]] bool first_time(std::string_view name, SimTime now);
  // True once `capacity` names are remembered: say so with the last one logged in full.
  bool full() const { return names_.size() >= capacity_; }
  // The names not remembered (set full) during the span, due at most once a period.
  [[nodiscard]] std::optional<RepeatedWarning::Summary> summary(SimTime now) { return overflow_.summary(now); }
  // Forgets every name (an episode ends: the same names are warned about again).
  void clear() { names_.clear(); }

  std::size_t size() const { return names_.size(); }
  std::size_t capacity() const { return capacity_; }
  bool contains(std::string_view name) const { return names_.find(name) != names_.end(); }

 private:
  std::size_t capacity_;
  std::set<std::string, std::less<>> names_;
  RepeatedWarning overflow_;
};

// ConnectionLogBudget — the lines a server writes about each connection (accepted, refused,
// closed and why), which a connection storm turns into a flood. At most `lines_per_period`
// such lines are written a period, one server's connections together; the rest are counted,
// and the count is said before the next line that is written ("… 297 connection lines not
// written in the last 1.2 s"). Three lines a second tell the whole story of the first
// connection of a storm (connected; closing and why; disconnected), and no line of it repeats
// within a second.
class ConnectionLogBudget {
 public:
  explicit ConnectionLogBudget(std::size_t lines_per_period = 3, Micros period = Micros{1'000'000});

  // True: write this line. False: it was counted instead. A count due is written to `logger`
  // first.
  [[nodiscard]] bool admit(const Logger& logger, SimTime now);
  std::uint64_t suppressed_total() const { return suppressed_total_; }

 private:
  std::size_t lines_per_period_;
  Micros period_;
  SimTime window_start_{0};
  std::size_t written_in_window_ = 0;
  std::uint64_t suppressed_ = 0;
  SimTime suppressed_since_{0};
  std::uint64_t suppressed_total_ = 0;
};

}  // namespace ocp
