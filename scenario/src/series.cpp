// Bounded series (series.hpp).
#include "scenario/series.hpp"

#include <algorithm>
#include <cmath>

namespace ocp::scenario {

void PlotSeries::add(SimTime time, double value) {
  if (!points_.empty() && in_last_ < stride_) {
    points_.back().value = std::max(points_.back().value, value);
    ++in_last_;
    return;
  }
  if (points_.size() == plot_capacity) {
    // Full: merge neighbours in pairs, so each point stands for twice as many samples.
    for (std::size_t i = 0; i < points_.size() / 2; ++i) {
      points_[i] = {points_[2 * i].time, std::max(points_[2 * i].value, points_[2 * i + 1].value)};
    }
    points_.resize(points_.size() / 2);
    stride_ *= 2;
  }
  points_.push_back({time, value});
  in_last_ = 1;
}

void PlotSeries::raise_last(double value) {
  if (!points_.empty()) points_.back().value = std::max(points_.back().value, value);
}

namespace {

std::int64_t thousandths(double value) { return std::llround(value * 1000.0); }

}  // namespace

void ValueHistogram::add(double value) {
  const std::int64_t key = thousandths(value);
  if (count_ == 0) {
    min_ = max_ = key;
  } else {
    min_ = std::min(min_, key);
    max_ = std::max(max_, key);
  }
  ++count_;
  sum_thousandths_ += static_cast<long double>(key);
  ++counts_[key >> shift_];
  if (counts_.size() > distinct_capacity) coarsen();
}

void ValueHistogram::coarsen() {
  while (counts_.size() > distinct_capacity) {
    std::map<std::int64_t, std::uint64_t> wider;
    for (const auto& [step, samples] : counts_) wider[step >> 1] += samples;
    counts_ = std::move(wider);
    ++shift_;
  }
}

void ValueHistogram::merge(const ValueHistogram& other) {
  if (other.count_ == 0) return;
  if (count_ == 0) {
    *this = other;
    return;
  }
  const int shift = std::max(shift_, other.shift_);
  std::map<std::int64_t, std::uint64_t> merged;
  for (const auto& [step, samples] : counts_) merged[step >> (shift - shift_)] += samples;
  for (const auto& [step, samples] : other.counts_) merged[step >> (shift - other.shift_)] += samples;
  counts_ = std::move(merged);
  shift_ = shift;
  count_ += other.count_;
  sum_thousandths_ += other.sum_thousandths_;
  min_ = std::min(min_, other.min_);
  max_ = std::max(max_, other.max_);
  coarsen();
}

double ValueHistogram::resolution_ms() const {
  return shift_ == 0 ? 0.0 : static_cast<double>(std::int64_t{1} << shift_) / 1000.0;
}

// The value of the sample at `rank` in sorted order: exact at step 1; else the middle of its
// step, kept within the exact min and max.
double ValueHistogram::value_at_rank(std::uint64_t rank) const {
  if (rank == 0) return static_cast<double>(min_) / 1000.0;
  if (rank + 1 >= count_) return static_cast<double>(max_) / 1000.0;
  std::uint64_t seen = 0;
  for (const auto& [step, samples] : counts_) {
    seen += samples;
    if (rank < seen) {
      if (shift_ == 0) return static_cast<double>(step) / 1000.0;
      const std::int64_t width = std::int64_t{1} << shift_;
      const std::int64_t middle = std::clamp(step * width + width / 2, min_, max_);
      return static_cast<double>(middle) / 1000.0;
    }
  }
  return static_cast<double>(max_) / 1000.0;
}

std::optional<double> ValueHistogram::aggregate(std::string_view name, double percentile) const {
  if (name == "count") return static_cast<double>(count_);
  if (count_ == 0 || name == "rate") return std::nullopt;
  if (name == "min") return static_cast<double>(min_) / 1000.0;
  if (name == "max") return static_cast<double>(max_) / 1000.0;
  if (name == "avg") return static_cast<double>(sum_thousandths_ / static_cast<long double>(count_) / 1000.0L);
  if (name == "med") percentile = 50;
  // Linear interpolation between the closest ranks, as k6 does.
  if (count_ == 1) return value_at_rank(0);
  const double rank = percentile / 100.0 * static_cast<double>(count_ - 1);
  const auto low = static_cast<std::uint64_t>(std::floor(rank));
  const std::uint64_t high = std::min(low + 1, count_ - 1);
  const double low_value = value_at_rank(low), high_value = value_at_rank(high);
  return low_value + (high_value - low_value) * (rank - static_cast<double>(low));
}

}  // namespace ocp::scenario
