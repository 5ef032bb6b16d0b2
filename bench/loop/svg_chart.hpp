#pragma once
// Minimal inline-SVG charts for the bench reports: no scripts, no fonts to fetch, no network.
//   xy_chart — lines or dots per series, linear or log10 axes (scale curves, time series);
//   log_histogram — fraction of samples per log-spaced bin, one step line per series.
#include <string>
#include <vector>

namespace ocp::bench {

struct XyPoint {
  double x = 0, y = 0;
};

struct XySeries {
  std::string name;
  std::string color;           // any SVG colour, e.g. "#1f77b4"
  std::vector<XyPoint> points;
  bool dots = false;           // scatter instead of a polyline
  bool dashed = false;         // polyline dashed (a floor or a limit beside the measured lines)
};

struct ChartOptions {
  std::string title;
  std::string x_label, y_label;
  bool log_x = false, log_y = false;
  int width_px = 760, height_px = 300;
};

std::string xy_chart(const std::vector<XySeries>& series, const ChartOptions& options);

struct HistogramSeries {
  std::string name;
  std::string color;
  std::vector<double> values;  // > 0; the bins are log-spaced
};

std::string log_histogram(const std::vector<HistogramSeries>& series, ChartOptions options, int bins_per_decade = 10);

}  // namespace ocp::bench
