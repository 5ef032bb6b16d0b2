// k6-style aggregates over a series.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "scenario/metrics.hpp"
#include "scenario/series.hpp"

namespace ocp::scenario {
namespace {

TEST(ScenarioMetrics, Aggregates) {
  ValueHistogram values;
  for (const double value : {5, 1, 4, 2, 3}) values.add(value);
  EXPECT_EQ(aggregate(values, "min", 0), 1.0);
  EXPECT_EQ(aggregate(values, "max", 0), 5.0);
  EXPECT_EQ(aggregate(values, "avg", 0), 3.0);
  EXPECT_EQ(aggregate(values, "med", 0), 3.0);
  EXPECT_EQ(aggregate(values, "count", 0), 5.0);
  EXPECT_EQ(aggregate(values, "p", 100), 5.0);
  EXPECT_EQ(aggregate(values, "p", 0), 1.0);
  EXPECT_DOUBLE_EQ(*aggregate(values, "p", 90), 4.6);   // linear between closest ranks
  const ValueHistogram empty;
  EXPECT_FALSE(aggregate(empty, "max", 0));
  EXPECT_EQ(aggregate(empty, "count", 0), 0.0);
}

TEST(ScenarioMetrics, Formatting) {
  EXPECT_EQ(format_number(150), "150");
  EXPECT_EQ(format_number(0.0199), "0.0199");
  EXPECT_EQ(format_number(388.5), "388.5");
  EXPECT_EQ(format_seconds(SimTime{12'500'000}), "12.5s");
}

}  // namespace
}  // namespace ocp::scenario

namespace ocp::scenario {
namespace {

// Percentile of a sorted vector, linear between closest ranks: what the histogram must give.
double sorted_reference_percentile(std::vector<double> values, double percentile) {
  std::sort(values.begin(), values.end());
  const double rank = percentile / 100.0 * static_cast<double>(values.size() - 1);
  const auto low = static_cast<std::size_t>(rank);
  const std::size_t high = std::min(low + 1, values.size() - 1);
  return values[low] + (values[high] - values[low]) * (rank - static_cast<double>(low));
}

TEST(ScenarioSeries, PercentilesAreExactWhileTheDistinctValuesFit) {
  ValueHistogram histogram;
  std::vector<double> values;
  for (int i = 0; i < 200'000; ++i) {
    const double value = static_cast<double>((i * 7919) % 4000) / 1000.0 + 20.0;   // 4000 distinct µs steps
    histogram.add(value);
    values.push_back(value);
  }
  EXPECT_EQ(histogram.resolution_ms(), 0.0);
  for (const double p : {0.0, 1.0, 50.0, 90.0, 99.0, 99.9, 100.0}) {
    EXPECT_DOUBLE_EQ(*histogram.aggregate("p", p), sorted_reference_percentile(values, p)) << "p(" << p << ")";
  }
}

TEST(ScenarioSeries, PastTheCapacityPercentilesAreWithinTheStatedResolution) {
  ValueHistogram histogram;
  std::vector<double> values;
  for (int i = 0; i < 1'000'000; ++i) {
    const double value = static_cast<double>((static_cast<std::int64_t>(i) * 104729) % 500'000) / 1000.0;   // 0..500 ms, µs steps
    histogram.add(value);
    values.push_back(value);
  }
  const double resolution = histogram.resolution_ms();
  EXPECT_GT(resolution, 0.0);
  EXPECT_LE(resolution, 0.256);
  EXPECT_EQ(histogram.aggregate("count", 0), 1'000'000.0);
  EXPECT_EQ(histogram.aggregate("min", 0), 0.0);
  EXPECT_EQ(histogram.aggregate("max", 0), 499.999);
  for (const double p : {1.0, 50.0, 95.0, 99.0}) {
    EXPECT_NEAR(*histogram.aggregate("p", p), sorted_reference_percentile(values, p), resolution) << "p(" << p << ")";
  }
}

TEST(ScenarioSeries, MergedHistogramsAggregateAsOne) {
  ValueHistogram a, b, both;
  for (int i = 0; i < 5000; ++i) {
    a.add(i % 97);
    b.add(100 + i % 13);
    both.add(i % 97);
    both.add(100 + i % 13);
  }
  a.merge(b);
  for (const char* name : {"count", "min", "max", "avg", "med"}) EXPECT_DOUBLE_EQ(*a.aggregate(name, 0), *both.aggregate(name, 0)) << name;
  EXPECT_DOUBLE_EQ(*a.aggregate("p", 95), *both.aggregate("p", 95));
}

TEST(ScenarioSeries, ThePlotIsBoundedAndKeepsItsSpikes) {
  PlotSeries plot;
  for (std::int64_t i = 0; i < 3'000'000; ++i) plot.add(SimTime{i * 10'000}, i == 1'234'567 ? 900.0 : 40.0);
  EXPECT_LE(plot.points().size(), PlotSeries::plot_capacity);
  EXPECT_GE(plot.points().size(), PlotSeries::plot_capacity / 2);
  EXPECT_EQ(plot.points().front().time, SimTime{0});
  double highest = 0;
  for (const Sample& point : plot.points()) highest = std::max(highest, point.value);
  EXPECT_EQ(highest, 900.0) << "the one spike survives the merging";
}

}  // namespace
}  // namespace ocp::scenario
