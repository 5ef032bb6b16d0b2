#pragma once
// A packet-delivery trace in Mahimahi's format (mm-link): each line is a whole number of
// milliseconds at which one delivery opportunity of `packet_bytes` occurs; several equal lines
// are several opportunities in that millisecond. The trace loops: its period is its last
// timestamp, so opportunity n lies at (n / count) × period + line[n % count].
// Immutable once parsed; directions share one through a shared_ptr (Impairments::trace).
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "ocp/error.hpp"
#include "ocp/time.hpp"

namespace ocp {

class DeliveryTrace {
 public:
  static constexpr std::size_t packet_bytes = 1500;        // Mahimahi's MTU
  static constexpr std::size_t max_lines = 10'000'000;     // bounds memory (80 MB)
  static constexpr std::int64_t max_timestamp_ms = 1'000'000'000;  // ~11.6 days per period

  // Errors are "NAME:LINE: reason" (or "NAME: reason" for the file as a whole), in `detail`.
  static Result<DeliveryTrace> parse(std::string_view text, const std::string& name);
  // Reading the file is the app layer's job: sim_app::load_delivery_trace (sim_app/file_loaders.hpp).

  const std::string& name() const { return name_; }
  Micros period() const { return Micros{millis_.back() * 1000}; }
  std::size_t opportunities_per_period() const { return millis_.size(); }
  // Time of opportunity `index`, from the trace's start.
  Micros time_of(std::uint64_t index) const;
  // The first opportunity at or after `elapsed` (≥ 0) from the trace's start.
  std::uint64_t first_at_or_after(Micros elapsed) const;

 private:
  DeliveryTrace(std::vector<std::int64_t> millis, std::string name)
      : millis_(std::move(millis)), name_(std::move(name)) {}
  std::vector<std::int64_t> millis_;  // non-decreasing, non-empty, last > 0
  std::string name_;
};

}  // namespace ocp
