// report.html (reports.hpp): one self-contained page — no script, no network. Latency over
// time as an inline SVG polyline per vehicle, fault intervals of both sides as bands under
// it, timeline events as marked lines, the verdicts, the seed and the reproduce command. The
// summary is embedded as JSON so a test (or a person) can check the page against summary.json.
#include <algorithm>
#include <cstdio>
#include <string>

#include "scenario/metrics.hpp"
#include "scenario/reports.hpp"
#include "sim_app/report_text.hpp"

namespace ocp::scenario {
namespace {

std::string escape(std::string_view text) { return report::markup_escape(text); }

std::string num(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.1f", value);
  return buffer;
}

constexpr const char* palette[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b"};
constexpr double width = 1100, plot_height = 260, left = 190, right = 10, top = 10, band_height = 14;
// A polyline of at most this many points per vehicle (max per bucket, so spikes survive).
constexpr std::size_t max_points = 1200;

// Where a time and a value fall on a panel (the latency plot, or a link panel under it).
struct PlotScale {
  double duration_us = 1;
  double y_max = 1;   // the value at the top of the panel
  double plot_width = width - left - right;
  double panel_top = top, panel_height = plot_height;
  double x_of(SimTime t) const { return left + plot_width * static_cast<double>(t.count()) / duration_us; }
  double y_of(double value) const { return panel_top + panel_height * (1.0 - value / y_max); }
};

// The y axis reaches 10 % above the highest latency_limit or sample, so that every line shows.
PlotScale plot_scale(const RunReport& report) {
  PlotScale scale;
  scale.duration_us = static_cast<double>(std::max<std::int64_t>(1, report.run->duration.count()));
  double y_max = 1;
  for (const VehicleSpec& spec : report.scenario->world.vehicles) {
    y_max = std::max(y_max, static_cast<double>(spec.streamer.latency_limit.count()) / 1000.0);
  }
  for (const auto& [name, data] : report.run->observations.vehicles) {
    for (const Sample& s : data.latency_ms.points()) y_max = std::max(y_max, s.value);
    for (const Sample& s : data.ping_ms.points()) y_max = std::max(y_max, s.value);
  }
  scale.y_max = y_max * 1.1;
  return scale;
}

// The plot's frame, its tick labels and each vehicle's latency_limit (usually one line).
void plot_axes(std::string& out, const PlotScale& scale, const Scenario& scenario) {
  out += "<rect x=\"" + num(left) + "\" y=\"" + num(top) + "\" width=\"" + num(scale.plot_width) + "\" height=\"" + num(plot_height) +
         "\" fill=\"#fafafa\" stroke=\"#999\"/>\n";
  for (int i = 0; i <= 4; ++i) {   // y axis ticks
    const double ms = scale.y_max * i / 4;
    out += "<text x=\"" + num(left - 4) + "\" y=\"" + num(scale.y_of(ms) + 3) + "\" text-anchor=\"end\">" + format_number(std::round(ms)) + "</text>\n";
  }
  out += "<text x=\"4\" y=\"" + num(top + 10) + "\">ms</text>\n";
  for (int i = 0; i <= 10; ++i) {   // x axis ticks
    const SimTime t{static_cast<std::int64_t>(scale.duration_us * i / 10)};
    out += "<text x=\"" + num(scale.x_of(t)) + "\" y=\"" + num(top + plot_height + 12) + "\" text-anchor=\"middle\">" + format_seconds(t) + "</text>\n";
  }
  for (const VehicleSpec& spec : scenario.world.vehicles) {
    const double limit = static_cast<double>(spec.streamer.latency_limit.count()) / 1000.0;
    out += "<line x1=\"" + num(left) + "\" x2=\"" + num(left + scale.plot_width) + "\" y1=\"" + num(scale.y_of(limit)) + "\" y2=\"" + num(scale.y_of(limit)) +
           "\" stroke=\"#d62728\" stroke-dasharray=\"2,2\"><title>latency_limit " + escape(spec.name) + "</title></line>\n";
  }
}

// At most max_points points: each is the highest sample of its bucket, so spikes survive.
void polyline(std::string& out, const PlotScale& scale, const PlotSeries& series, const std::string& color,
              const char* style, const std::string& title) {
  const std::vector<Sample>& samples = series.points();   // already at most plot_capacity
  if (samples.empty()) return;
  const std::size_t bucket = std::max<std::size_t>(1, (samples.size() + max_points - 1) / max_points);
  out += "<polyline fill=\"none\" stroke=\"" + color + "\" stroke-width=\"1\" " + style + " points=\"";
  for (std::size_t i = 0; i < samples.size(); i += bucket) {
    double peak = 0;
    for (std::size_t j = i; j < std::min(samples.size(), i + bucket); ++j) peak = std::max(peak, samples[j].value);
    out += num(scale.x_of(samples[i].time)) + "," + num(scale.y_of(peak)) + " ";
  }
  out += "\"><title>" + escape(title) + "</title></polyline>\n";
}

// A vehicle's latency (solid) and ping (dotted) share its colour.
void latency_lines(std::string& out, const PlotScale& scale, const Observations& obs) {
  std::size_t color = 0;
  for (const auto& [name, data] : obs.vehicles) {
    const std::string stroke = palette[color++ % 6];
    polyline(out, scale, data.latency_ms.plot(), stroke, "", "latency_ms " + name);
    polyline(out, scale, data.ping_ms.plot(), stroke, "stroke-dasharray=\"1,2\" opacity=\"0.7\"", "ping_ms " + name);
  }
}

// The link panels: each direction's delivered throughput (Mbit/s) and queueing delay (ms),
// per vehicle (to_player solid, to_streamer dashed), on the latency plot's time axis.
constexpr double link_panel_height = 110, link_panel_gap = 22;

bool has_link_series(const Observations& obs) {
  for (const auto& [name, data] : obs.vehicles) {
    if (!data.to_player_link.throughput_mbps.empty() || !data.to_streamer_link.throughput_mbps.empty()) return true;
  }
  return false;
}

using LinkSeriesField = PlotSeries LinkSeries::*;

// One panel: frame, y ticks, its name, and a line per (vehicle, direction). Returns its bottom.
double link_panel(std::string& out, PlotScale scale, const Observations& obs, LinkSeriesField field, const char* what) {
  for (const auto& [name, data] : obs.vehicles) {
    for (const Sample& s : (data.to_player_link.*field).points()) scale.y_max = std::max(scale.y_max, s.value * 1.1);
    for (const Sample& s : (data.to_streamer_link.*field).points()) scale.y_max = std::max(scale.y_max, s.value * 1.1);
  }
  out += "<rect x=\"" + num(left) + "\" y=\"" + num(scale.panel_top) + "\" width=\"" + num(scale.plot_width) + "\" height=\"" +
         num(scale.panel_height) + "\" fill=\"#fafafa\" stroke=\"#999\"/>\n";
  for (int i = 0; i <= 2; ++i) {
    const double value = scale.y_max * i / 2;
    out += "<text x=\"" + num(left - 4) + "\" y=\"" + num(scale.y_of(value) + 3) + "\" text-anchor=\"end\">" +
           format_number(value < 10 ? std::round(value * 10) / 10 : std::round(value)) + "</text>\n";
  }
  out += "<text x=\"4\" y=\"" + num(scale.panel_top + 10) + "\">" + escape(what) + "</text>\n";
  std::size_t color = 0;
  for (const auto& [name, data] : obs.vehicles) {
    const std::string stroke = palette[color++ % 6];
    const std::string metric = field == &LinkSeries::throughput_mbps ? "throughput_mbps " : "queueing_delay_ms ";
    polyline(out, scale, data.to_player_link.*field, stroke, "", metric + name + " to_player");
    polyline(out, scale, data.to_streamer_link.*field, stroke, "stroke-dasharray=\"4,2\"", metric + name + " to_streamer");
  }
  return scale.panel_top + scale.panel_height;
}

// Both link panels from `panels_top`; returns where the next thing may start.
double link_panels(std::string& out, const PlotScale& latency, const Observations& obs, double panels_top) {
  if (!has_link_series(obs)) return panels_top;
  PlotScale scale = latency;
  scale.y_max = 0.1;
  scale.panel_height = link_panel_height;
  scale.panel_top = panels_top;
  const double throughput_bottom = link_panel(out, scale, obs, &LinkSeries::throughput_mbps, "link Mbit/s");
  scale.panel_top = throughput_bottom + link_panel_gap / 2;
  return link_panel(out, scale, obs, &LinkSeries::queueing_delay_ms, "queueing ms") + link_panel_gap / 2;
}

// A dashed vertical per fired timeline event, down through the bands, named at the top.
void event_markers(std::string& out, const PlotScale& scale, const std::vector<FiredEvent>& fired, double height) {
  for (const FiredEvent& event : fired) {
    const std::string x = num(scale.x_of(event.at));
    out += "<line x1=\"" + x + "\" x2=\"" + x + "\" y1=\"" + num(top) + "\" y2=\"" + num(height - 20) +
           "\" stroke=\"#555\" stroke-dasharray=\"4,3\"><title>" + escape(format_seconds(event.at) + " " + event.label) + "</title></line>\n";
    out += "<text x=\"" + x + "\" y=\"" + num(top + 10) + "\" transform=\"rotate(90 " + x + " " + num(top + 10) +
           ")\" fill=\"#555\">" + escape(event.name.empty() ? event.label : event.name) + "</text>\n";
  }
}

// One band per (vehicle, fault) under the plot, a rectangle per interval (to the end if still active).
void fault_bands(std::string& out, const PlotScale& scale, const RunResult& run, double bands_top) {
  double y = bands_top;
  for (const auto& [fault_key, list] : run.observations.faults) {
    const bool vehicle_side = fault_side(fault_key.second) == FaultSide::vehicle;
    const std::string fill = vehicle_side ? "#e377c2" : "#17becf";
    out += "<text x=\"" + num(left - 4) + "\" y=\"" + num(y + 10) + "\" text-anchor=\"end\" font-size=\"8\">" +
           escape(fault_key.first + " " + std::string(fault_identifier(fault_key.second))) + "</text>\n";
    for (const Interval& interval : list) {
      const double x1 = scale.x_of(interval.start);
      const double x2 = scale.x_of(interval.end.value_or(run.duration));
      out += "<rect x=\"" + num(x1) + "\" y=\"" + num(y) + "\" width=\"" + num(std::max(1.0, x2 - x1)) + "\" height=\"" + num(band_height - 2) +
             "\" fill=\"" + fill + "\"><title>" + escape(std::string(fault_identifier(fault_key.second)) + " (" +
                                                         std::string(fault_side_name(fault_side(fault_key.second))) + ") " +
                                                         format_seconds(interval.start) + " – " +
                                                         (interval.end ? format_seconds(*interval.end) : "end")) + "</title></rect>\n";
    }
    y += band_height;
  }
}

std::string svg(const RunReport& report) {
  const PlotScale scale = plot_scale(report);
  std::string body;
  const double bands_top = link_panels(body, scale, report.run->observations, top + plot_height + 24);
  const double height = bands_top + band_height * static_cast<double>(report.run->observations.faults.size()) + 20;
  std::string out = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + num(width) + "\" height=\"" + num(height) +
                    "\" font-family=\"sans-serif\" font-size=\"10\">\n";
  plot_axes(out, scale, *report.scenario);
  latency_lines(out, scale, report.run->observations);
  out += body;
  event_markers(out, scale, report.run->fired, height);
  fault_bands(out, scale, *report.run, bands_top);
  out += "</svg>\n";
  return out;
}

}  // namespace

std::string report_html(const RunReport& report, const std::string& summary) {
  const Scenario& scenario = *report.scenario;
  const bool passed = all_passed(report.verdicts) && !report.run->interrupted;
  std::string embedded = summary;
  for (std::size_t at = 0; (at = embedded.find("</", at)) != std::string::npos; at += 3) embedded.replace(at, 2, "<\\/");

  std::string out = "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" + escape(scenario.name) + " — ocp_scenario</title>\n";
  out += "<style>body{font-family:sans-serif;margin:20px}td,th{padding:2px 8px;text-align:left}"
         ".pass{color:#2ca02c}.fail{color:#d62728}.skip{color:#7f7f7f}code{background:#eee;padding:2px}</style></head><body>\n";
  const char* headline = report.run->interrupted ? "skip\">○ interrupted" : passed ? "pass\">✓ passed" : "fail\">✗ failed";
  out += "<h1>" + escape(scenario.name) + " <span class=\"" + headline + "</span></h1>\n";
  if (report.run->interrupted) {
    out += "<p class=\"skip\">Interrupted at " + format_seconds(report.run->ran) + " of " +
           format_seconds(report.run->duration) + ": expectations that needed the rest of the run are not judged.</p>\n";
  }
  if (!scenario.description.empty()) out += "<p>" + escape(scenario.description) + "</p>\n";
  out += "<p>seed <b>" + std::to_string(report.run->seed) + "</b>, " + format_seconds(report.run->duration) +
         " simulated. Reproduce: <code>" + escape(report.reproduce) + "</code></p>\n";
  out += "<h2>Latency (ms) and faults</h2>\n<p>Lines: measured latency per vehicle (red dashes: latency_limit); "
         "dotted: ping per vehicle (the Player's ping_latency_ms, sampled every 100 ms); "
         "bands: fault intervals (pink: vehicle side, teal: operator side); dashed verticals: timeline events. "
         "Under it, when the run observed its links: each direction's delivered throughput (Mbit/s per 100 ms) and "
         "queueing delay (the highest one-way delay less the set propagation delay per 100 ms; solid: to_player, "
         "the vehicle's uplink; dashed: to_streamer).</p>\n";
  out += svg(report);
  out += "<h2>Verdicts</h2>\n<table><tr><th></th><th>expectation</th><th>expected</th><th>actual</th><th>line</th></tr>\n";
  for (const Verdict& verdict : report.verdicts) {
    const char* mark = verdict.passed ? "pass\"><td>✓" : verdict.interrupted ? "skip\"><td>○" : "fail\"><td>✗";
    out += std::string("<tr class=\"") + mark + "</td><td>" + escape(verdict.title) +
           "</td><td>" + escape(verdict.expected) + "</td><td>" + escape(verdict.actual) + "</td><td>" +
           std::to_string(verdict.mark.line) + "</td></tr>\n";
  }
  out += "</table>\n<h2>Timeline</h2>\n<ul>\n";
  for (const FiredEvent& event : report.run->fired) {
    out += "<li>" + format_seconds(event.at) + " " + escape(event.label) + (event.name.empty() ? "" : " (" + escape(event.name) + ")") + "</li>\n";
  }
  out += "</ul>\n<script type=\"application/json\" id=\"summary\">\n" + embedded + "</script>\n</body></html>\n";
  return out;
}

}  // namespace ocp::scenario
