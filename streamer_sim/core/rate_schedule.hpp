#pragma once
// Absolute deadlines for a loop running at a (possibly fractional) rate: iteration k is due
// at start + round(k · 1e6 / rate_hz) µs, so 30 Hz never drifts although 1e6/30 is not whole.
#include <cmath>
#include <cstdint>

#include "ocp/time.hpp"

namespace ocp::streamer {

class RateSchedule {
 public:
  RateSchedule(SimTime start, double rate_hz) : start_(start), rate_hz_(rate_hz) {}

  bool valid() const { return rate_hz_ > 0.0 && std::isfinite(rate_hz_); }
  SimTime deadline(std::uint64_t index) const {
    const double offset_us = static_cast<double>(index) * 1e6 / rate_hz_;
    return start_ + Micros{std::llround(offset_us)};
  }
  // The first index whose deadline is strictly after `time`.
  std::uint64_t first_index_after(SimTime time, std::uint64_t from_index) const {
    std::uint64_t index = from_index;
    while (deadline(index) <= time) ++index;
    return index;
  }

 private:
  SimTime start_;
  double rate_hz_;
};

}  // namespace ocp::streamer
