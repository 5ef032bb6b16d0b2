#pragma once
// Min/avg/max of the latency samples of one status period, so a status line describes its
// whole second instead of whichever sample happened to be latest.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>

#include <fmt/format.h>

namespace ocp {

class LatencyWindow {
 public:
  void add(std::uint64_t latency_ms) {
    min_ = std::min(min_, latency_ms);
    max_ = std::max(max_, latency_ms);
    sum_ += latency_ms;
    ++count_;
  }
  bool empty() const { return count_ == 0; }
  std::uint64_t min() const { return min_; }
  std::uint64_t max() const { return max_; }
  double average() const { return count_ == 0 ? 0.0 : static_cast<double>(sum_) / static_cast<double>(count_); }
  // "min/avg/max 60/71/83 ms", or `when_empty`.
  std::string format(const std::string& when_empty = "n/a") const {
    if (empty()) return when_empty;
    return fmt::format("min/avg/max {}/{:.0f}/{} ms", min_, average(), max_);
  }
  void reset() { *this = LatencyWindow{}; }

 private:
  std::uint64_t min_ = std::numeric_limits<std::uint64_t>::max();
  std::uint64_t max_ = 0;
  std::uint64_t sum_ = 0;
  std::uint64_t count_ = 0;
};

}  // namespace ocp
