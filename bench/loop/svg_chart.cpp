#include "svg_chart.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace ocp::bench {

namespace {

constexpr double margin_left = 70, margin_right = 150, margin_top = 30, margin_bottom = 45;

std::string escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '&') out += "&amp;";
    else out += c;
  }
  return out;
}

struct Axis {
  double low = 0, high = 1;
  bool log = false;
  double map(double value, double from_px, double to_px) const {
    const double a = log ? std::log10(low) : low;
    const double b = log ? std::log10(high) : high;
    const double v = log ? std::log10(std::max(value, low)) : value;
    return from_px + (to_px - from_px) * (b > a ? (v - a) / (b - a) : 0.5);
  }
  std::vector<double> ticks() const {
    std::vector<double> out;
    if (log) {
      for (double decade = std::pow(10.0, std::floor(std::log10(low))); decade <= high * 1.0001; decade *= 10) {
        if (decade >= low * 0.9999) out.push_back(decade);
      }
      return out;
    }
    const double span = high - low;
    const double raw = span / 5;
    const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
    double step = magnitude;
    for (double factor : {1.0, 2.0, 5.0, 10.0}) {
      if (raw <= factor * magnitude) {
        step = factor * magnitude;
        break;
      }
    }
    for (double tick = std::ceil(low / step) * step; tick <= high + step * 1e-9; tick += step) out.push_back(tick);
    return out;
  }
};

Axis make_axis(const std::vector<XySeries>& series, bool log, bool is_x) {
  double low = std::numeric_limits<double>::max(), high = std::numeric_limits<double>::lowest();
  for (const auto& one : series) {
    for (const auto& point : one.points) {
      const double value = is_x ? point.x : point.y;
      if (log && value <= 0) continue;
      low = std::min(low, value);
      high = std::max(high, value);
    }
  }
  if (low > high) {
    low = log ? 1 : 0;
    high = log ? 10 : 1;
  }
  Axis axis;
  axis.log = log;
  if (log) {
    axis.low = std::pow(10.0, std::floor(std::log10(low)));
    axis.high = std::pow(10.0, std::ceil(std::log10(high)));
    if (axis.high <= axis.low) axis.high = axis.low * 10;
  } else {
    axis.low = is_x ? low : std::min(0.0, low);
    axis.high = high > axis.low ? high : axis.low + 1;
    if (!is_x) axis.high *= 1.05;
  }
  return axis;
}

std::string format_tick(double value) {
  if (value != 0 && (std::fabs(value) >= 1e5 || std::fabs(value) < 1e-2)) return fmt::format("{:.0e}", value);
  return fmt::format("{:g}", value);
}

}  // namespace

std::string xy_chart(const std::vector<XySeries>& series, const ChartOptions& options) {
  const double width = options.width_px, height = options.height_px;
  const double left = margin_left, right = width - margin_right, top = margin_top, bottom = height - margin_bottom;
  const Axis x_axis = make_axis(series, options.log_x, true);
  const Axis y_axis = make_axis(series, options.log_y, false);
  std::string svg = fmt::format(
      R"(<svg xmlns="http://www.w3.org/2000/svg" width="{0}" height="{1}" viewBox="0 0 {0} {1}" font-family="sans-serif" font-size="11">)"
      "\n<rect width=\"{0}\" height=\"{1}\" fill=\"white\"/>\n"
      R"(<text x="{2}" y="18" font-size="13" font-weight="bold">{3}</text>)"
      "\n",
      width, height, left, escape(options.title));
  for (double tick : x_axis.ticks()) {
    const double x = x_axis.map(tick, left, right);
    svg += fmt::format(R"(<line x1="{0:.1f}" y1="{1}" x2="{0:.1f}" y2="{2}" stroke="#ddd"/><text x="{0:.1f}" y="{3}" text-anchor="middle">{4}</text>)"
                       "\n", x, top, bottom, bottom + 14, format_tick(tick));
  }
  for (double tick : y_axis.ticks()) {
    const double y = y_axis.map(tick, bottom, top);
    svg += fmt::format(R"(<line x1="{0}" y1="{1:.1f}" x2="{2}" y2="{1:.1f}" stroke="#ddd"/><text x="{3}" y="{4:.1f}" text-anchor="end">{5}</text>)"
                       "\n", left, y, right, left - 4, y + 4, format_tick(tick));
  }
  svg += fmt::format(R"(<rect x="{}" y="{}" width="{}" height="{}" fill="none" stroke="#333"/>)" "\n",
                     left, top, right - left, bottom - top);
  svg += fmt::format(R"(<text x="{}" y="{}" text-anchor="middle">{}</text>)" "\n", (left + right) / 2, height - 8,
                     escape(options.x_label));
  svg += fmt::format(R"svg(<text transform="translate(14,{}) rotate(-90)" text-anchor="middle">{}</text>)svg" "\n",
                     (top + bottom) / 2, escape(options.y_label));
  double legend_y = top + 10;
  for (const auto& one : series) {
    if (one.dots) {
      svg += fmt::format(R"(<g fill="{}" fill-opacity="0.5">)", one.color);
      for (const auto& point : one.points) {
        if ((options.log_x && point.x <= 0) || (options.log_y && point.y <= 0)) continue;
        svg += fmt::format(R"(<circle cx="{:.1f}" cy="{:.1f}" r="1.3"/>)", x_axis.map(point.x, left, right),
                           y_axis.map(point.y, bottom, top));
      }
      svg += "</g>\n";
    } else {
      svg += fmt::format(R"(<polyline fill="none" stroke="{}" stroke-width="1.6"{} points=")", one.color,
                         one.dashed ? R"( stroke-dasharray="6 4")" : "");
      for (const auto& point : one.points) {
        if ((options.log_x && point.x <= 0) || (options.log_y && point.y <= 0)) continue;
        svg += fmt::format("{:.1f},{:.1f} ", x_axis.map(point.x, left, right), y_axis.map(point.y, bottom, top));
      }
      svg += "\"/>\n";
      for (const auto& point : one.points) {
        if ((options.log_x && point.x <= 0) || (options.log_y && point.y <= 0)) continue;
        if (one.points.size() <= 12) {
          svg += fmt::format(R"(<circle cx="{:.1f}" cy="{:.1f}" r="2.5" fill="{}"/>)", x_axis.map(point.x, left, right),
                             y_axis.map(point.y, bottom, top), one.color);
        }
      }
    }
    svg += fmt::format(R"(<rect x="{}" y="{}" width="10" height="10" fill="{}"/><text x="{}" y="{}">{}</text>)" "\n",
                       right + 8, legend_y - 9, one.color, right + 22, legend_y, escape(one.name));
    legend_y += 16;
  }
  return svg + "</svg>\n";
}

std::string log_histogram(const std::vector<HistogramSeries>& series, ChartOptions options, int bins_per_decade) {
  double low = std::numeric_limits<double>::max(), high = 0;
  for (const auto& one : series) {
    for (double value : one.values) {
      if (value <= 0) continue;
      low = std::min(low, value);
      high = std::max(high, value);
    }
  }
  if (high <= 0) {
    low = 1;
    high = 10;
  }
  const double first = std::floor(std::log10(low) * bins_per_decade) / bins_per_decade;
  const double last = std::ceil(std::log10(high) * bins_per_decade) / bins_per_decade + 1.0 / bins_per_decade;
  const auto bins = static_cast<std::size_t>(std::lround((last - first) * bins_per_decade));
  std::vector<XySeries> lines;
  for (const auto& one : series) {
    std::vector<double> counts(bins, 0.0);
    std::size_t total = 0;
    for (double value : one.values) {
      if (value <= 0) continue;
      const auto bin = static_cast<std::size_t>(std::clamp((std::log10(value) - first) * bins_per_decade, 0.0,
                                                           static_cast<double>(bins - 1)));
      counts[bin] += 1;
      ++total;
    }
    XySeries line{one.name, one.color, {}, false};
    for (std::size_t bin = 0; bin < bins; ++bin) {
      const double y = total ? 100.0 * counts[bin] / static_cast<double>(total) : 0.0;
      line.points.push_back({std::pow(10.0, first + static_cast<double>(bin) / bins_per_decade), y});
      line.points.push_back({std::pow(10.0, first + static_cast<double>(bin + 1) / bins_per_decade), y});
    }
    lines.push_back(std::move(line));
  }
  options.log_x = true;
  options.log_y = false;
  if (options.y_label.empty()) options.y_label = "% of samples";
  return xy_chart(lines, options);
}

}  // namespace ocp::bench
