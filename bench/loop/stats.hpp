#pragma once
// Percentile summaries of sample vectors, shared by every ocp_bench report.
#include <algorithm>
#include <cstddef>
#include <vector>

namespace ocp::bench {

struct Summary {
  std::size_t count = 0;
  double p50 = 0, p90 = 0, p99 = 0, p999 = 0, max = 0, mean = 0;
};

// Nearest-rank on a sorted copy; an empty input gives all zeros.
inline double percentile_sorted(const std::vector<double>& sorted, double fraction) {
  if (sorted.empty()) return 0.0;
  const auto index = static_cast<std::size_t>(fraction * static_cast<double>(sorted.size() - 1) + 0.5);
  return sorted[std::min(index, sorted.size() - 1)];
}

inline Summary summarize(std::vector<double> values) {
  Summary summary;
  if (values.empty()) return summary;
  std::sort(values.begin(), values.end());
  summary.count = values.size();
  summary.p50 = percentile_sorted(values, 0.50);
  summary.p90 = percentile_sorted(values, 0.90);
  summary.p99 = percentile_sorted(values, 0.99);
  summary.p999 = percentile_sorted(values, 0.999);
  summary.max = values.back();
  double total = 0;
  for (double value : values) total += value;
  summary.mean = total / static_cast<double>(values.size());
  return summary;
}

}  // namespace ocp::bench
