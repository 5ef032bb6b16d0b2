#pragma once
// A run's measured series in bounded memory, however long the run (issue #36: a 24 h run
// keeps as little as a 10 s one). Two parts:
//   * PlotSeries — what report.html draws: every sample while there are at most
//     plot_capacity of them; past that, neighbouring points merge in pairs (the higher value,
//     at the first one's time, so spikes survive) and each later point stands for as many
//     samples (stride()).
//   * ValueHistogram — what verdicts and summary.json compute (count, min, max, avg, med,
//     p(N)): a count per distinct value, in steps of 0.001 (the series are milliseconds from
//     microseconds). Count, min, max and avg are always exact; med and p(N) are exact while at
//     most distinct_capacity distinct values were seen, and past that within resolution_ms()
//     (the step doubles each time the values would exceed the capacity).
// A Series is both; the link panels (LinkSeries) need only the plot.
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string_view>
#include <vector>

#include "ocp/time.hpp"

namespace ocp::scenario {

struct Sample {
  SimTime time{0};
  double value = 0.0;
  bool operator==(const Sample&) const = default;
};

class PlotSeries {
 public:
  static constexpr std::size_t plot_capacity = std::size_t{1} << 14;   // 164 s of 100 Hz samples kept whole

  void add(SimTime time, double value);
  // Raises the newest sample to `value` if it is higher (a bucket still filling: link_series.cpp).
  void raise_last(double value);
  const std::vector<Sample>& points() const { return points_; }
  std::uint64_t stride() const { return stride_; }   // samples per point (1: every sample)
  bool empty() const { return points_.empty(); }

 private:
  std::vector<Sample> points_;
  std::uint64_t stride_ = 1;
  std::uint64_t in_last_ = 0;   // samples merged into the last point so far
};

class ValueHistogram {
 public:
  static constexpr std::size_t distinct_capacity = 4096;

  void add(double value);
  void merge(const ValueHistogram& other);
  std::uint64_t count() const { return count_; }
  // count, min, max, avg, med, p (with `percentile`); nullopt on no samples (count gives 0)
  // and for rate (only counters have one).
  std::optional<double> aggregate(std::string_view name, double percentile) const;
  // 0 while every value is counted exactly; else the width of a counted step, in ms.
  double resolution_ms() const;

 private:
  void coarsen();                                      // halves the step
  double value_at_rank(std::uint64_t rank) const;      // 0-based, over the sorted values
  std::map<std::int64_t, std::uint64_t> counts_;       // step index → samples
  int shift_ = 0;                                      // a step is 2^shift_ thousandths
  std::uint64_t count_ = 0;
  long double sum_thousandths_ = 0;                    // exact: the values are whole thousandths
  std::int64_t min_ = 0, max_ = 0;                     // in thousandths
};

class Series {
 public:
  void add(SimTime time, double value) {
    plot_.add(time, value);
    values_.add(value);
  }
  const PlotSeries& plot() const { return plot_; }
  const std::vector<Sample>& points() const { return plot_.points(); }
  const ValueHistogram& values() const { return values_; }
  std::uint64_t count() const { return values_.count(); }
  bool empty() const { return values_.count() == 0; }

 private:
  PlotSeries plot_;
  ValueHistogram values_;
};

}  // namespace ocp::scenario
