// k6-style aggregates over a series.
#include <gtest/gtest.h>

#include "scenario/metrics.hpp"

namespace ocp::scenario {
namespace {

TEST(ScenarioMetrics, Aggregates) {
  std::vector<double> values{5, 1, 4, 2, 3};
  EXPECT_EQ(aggregate(values, "min", 0), 1.0);
  EXPECT_EQ(aggregate(values, "max", 0), 5.0);
  EXPECT_EQ(aggregate(values, "avg", 0), 3.0);
  EXPECT_EQ(aggregate(values, "med", 0), 3.0);
  EXPECT_EQ(aggregate(values, "count", 0), 5.0);
  EXPECT_EQ(aggregate(values, "p", 100), 5.0);
  EXPECT_EQ(aggregate(values, "p", 0), 1.0);
  EXPECT_DOUBLE_EQ(*aggregate(values, "p", 90), 4.6);   // linear between closest ranks
  std::vector<double> empty;
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
