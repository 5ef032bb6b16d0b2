#include "loop_report.hpp"

#include <fmt/format.h>

#include <sstream>

#include "json_text.hpp"
#include "svg_chart.hpp"

namespace ocp::bench {

namespace {

std::string fault_list(const std::vector<FaultRecord>& faults) {
  if (faults.empty()) return "none";
  std::string out;
  for (const auto& fault : faults) {
    if (!out.empty()) out += ", ";
    out += fmt::format("{}{} at {:.2f} s{}", fault.active ? "+" : "-", fault.id, fault.at_s,
                       fault.before_connect ? " (before connect)" : "");
  }
  return out;
}

double ratio(double a, double b) { return b > 0 ? a / b : 0.0; }

void print_summary_row(std::ostream& out, const std::string& what, const Summary& s, double scale,
                       const std::string& unit) {
  out << fmt::format("  {:<34} {:>9.1f} {:>9.1f} {:>9.1f} {:>9.1f} {:>9.1f}  {} (n={})\n", what, s.p50 * scale,
                     s.p90 * scale, s.p99 * scale, s.p999 * scale, s.max * scale, unit, s.count);
}

void print_client(std::ostream& out, const ClientFigures& figures) {
  out << fmt::format("{}\n", figures.name);
  out << fmt::format("  {:<34} {:>9} {:>9} {:>9} {:>9} {:>9}\n", "", "p50", "p90", "p99", "p99.9", "max");
  print_summary_row(out, "echo delay", figures.echo_us, 1.0, "µs");
  print_summary_row(out, "OCP latency (latency_ms)", figures.latency_ms, 1.0, "ms");
  print_summary_row(out, "tick lateness", figures.tick_lateness_us, 1.0, "µs");
  out << fmt::format("  control frames {}, responses {} ({:.1f}/s), largest gap between responses {:.1f} ms, "
                     "connections {}\n",
                     figures.control_frames, figures.responses, figures.responses_per_s,
                     figures.max_response_gap_ms, figures.connections);
  out << fmt::format("  faults: {}\n", fault_list(figures.faults));
}

std::string client_json(const ClientFigures& figures) {
  std::string faults = "[";
  for (const auto& fault : figures.faults) {
    if (faults.size() > 1) faults += ",";
    faults += fmt::format(R"({{"at_s":{},"id":{},"active":{},"before_connect":{}}})", json_number(fault.at_s),
                          json_string(fault.id), fault.active, fault.before_connect);
  }
  faults += "]";
  return fmt::format(
      R"({{"name":{},"echo_delay_us":{},"control_frames":{},"responses":{},"responses_per_s":{},)"
      R"("max_response_gap_ms":{},"latency_ms":{},"tick_lateness_us":{},"connections":{},"faults":{}}})",
      json_string(figures.name), json_summary(figures.echo_us), figures.control_frames, figures.responses,
      json_number(figures.responses_per_s), json_number(figures.max_response_gap_ms),
      json_summary(figures.latency_ms), json_summary(figures.tick_lateness_us), figures.connections, faults);
}

// The references the client is divided by, in the order they are printed.
struct RatioRow {
  std::string label;   // terminal
  std::string key;     // JSON: echo_p50_vs_<key>
  Summary reference;
};

std::vector<RatioRow> ratio_rows(const LoopResult& result) {
  std::vector<RatioRow> rows;
  if (result.floor_echo_us) rows.push_back({"vs machine floor", "floor", *result.floor_echo_us});
  if (result.bare_client) rows.push_back({"vs bare client (same Streamer)", "bare_client", result.bare_client->echo_us});
  if (result.timer_client) rows.push_back({"vs 10 ms timer client", "timer_client", result.timer_client->echo_us});
  return rows;
}

}  // namespace

void print_table(std::ostream& out, const LoopResult& result) {
  out << fmt::format("\nocp_bench loop: {:.1f} s on 127.0.0.1:{}{}\n", result.duration_s, result.port,
                     result.command.empty() ? "" : " — " + result.command);
  if (result.child_exit) out << fmt::format("client process exited early with status {}\n", *result.child_exit);
  if (result.interrupted) out << "interrupted: Ctrl-C cut the measurement short; the figures cover what ran\n";
  print_client(out, result.client);
  if (result.bare_client) print_client(out, *result.bare_client);
  if (result.timer_client) print_client(out, *result.timer_client);
  if (result.floor_echo_us) {
    out << "machine floor (bare blocking-socket echo)\n";
    print_summary_row(out, "echo round trip", *result.floor_echo_us, 1.0, "µs");
  }
  const std::vector<RatioRow> rows = ratio_rows(result);
  if (!rows.empty()) {
    const Summary& client = result.client.echo_us;
    out << "client echo delay as a ratio (same run)\n";
    out << fmt::format("  {:<34} {:>9} {:>9} {:>9}\n", "", "p50", "p99", "max");
    for (const RatioRow& row : rows) {
      out << fmt::format("  {:<34} {:>8.2f}× {:>8.2f}× {:>8.2f}×\n", row.label, ratio(client.p50, row.reference.p50),
                         ratio(client.p99, row.reference.p99), ratio(client.max, row.reference.max));
    }
  }
  if (!result.gates.empty()) {
    out << "gates\n";
    for (const GateResult& gate : result.gates) {
      out << fmt::format("  {} {:<42} expected {:<12} actual {}\n", gate.passed ? "✓" : "✗", gate.name, gate.expected,
                         gate.actual);
    }
  }
}

std::string to_json(const LoopResult& result) {
  std::string json = fmt::format(R"({{"tool":"ocp_bench loop","command":{},"port":{},"duration_s":{},)",
                                 json_string(result.command), result.port, json_number(result.duration_s));
  json += fmt::format(R"("child_exit":{},"interrupted":{},"faults_after_connect":{},"client":{})",
                      result.child_exit ? std::to_string(*result.child_exit) : "null", result.interrupted, result.faults_after_connect(),
                      client_json(result.client));
  if (result.floor_echo_us) json += fmt::format(R"(,"floor_echo_us":{})", json_summary(*result.floor_echo_us));
  if (result.bare_client) json += fmt::format(R"(,"bare_client":{})", client_json(*result.bare_client));
  if (result.timer_client) json += fmt::format(R"(,"timer_client":{})", client_json(*result.timer_client));
  const std::vector<RatioRow> rows = ratio_rows(result);
  if (!rows.empty()) {
    const Summary& client = result.client.echo_us;
    std::string ratios;
    for (const RatioRow& row : rows) {
      ratios += fmt::format(R"({}"echo_p50_vs_{}":{},"echo_p99_vs_{}":{})", ratios.empty() ? "" : ",", row.key,
                            json_number(ratio(client.p50, row.reference.p50)), row.key,
                            json_number(ratio(client.p99, row.reference.p99)));
    }
    json += R"(,"ratios":{)" + ratios + "}";
  }
  std::string gates;
  for (const GateResult& gate : result.gates) {
    gates += fmt::format(R"({}{{"name":{},"expected":{},"actual":{},"passed":{}}})", gates.empty() ? "" : ",",
                         json_string(gate.name), json_string(gate.expected), json_string(gate.actual), gate.passed);
  }
  json += R"(,"gates":[)" + gates + "]";
  return json + "}\n";
}

std::string to_html(const LoopResult& result) {
  std::vector<HistogramSeries> histogram{{result.client.name, "#1f77b4", result.client.echo_delays_us}};
  if (result.floor_echo_us) histogram.push_back({"machine floor", "#2ca02c", result.floor_echo_delays_us});
  if (result.bare_client) histogram.push_back({"bare client", "#ff7f0e", result.bare_client->echo_delays_us});
  if (result.timer_client) histogram.push_back({"10 ms timer client", "#d62728", result.timer_client->echo_delays_us});
  ChartOptions histogram_options;
  histogram_options.title = "Echo delay: control frame out → first response with its pair";
  histogram_options.x_label = "echo delay, µs (log)";

  auto to_points = [](const std::vector<TimePoint>& series) {
    std::vector<XyPoint> points;
    points.reserve(series.size());
    for (const auto& point : series) points.push_back({point.at_s, point.value});
    return points;
  };
  std::vector<XySeries> echo_series{{result.client.name, "#1f77b4", to_points(result.client.echo_series_us), true}};
  if (result.bare_client) {
    echo_series.push_back({"bare client", "#ff7f0e", to_points(result.bare_client->echo_series_us), true});
  }
  if (result.timer_client) {
    echo_series.push_back({"10 ms timer client", "#d62728", to_points(result.timer_client->echo_series_us), true});
  }
  ChartOptions echo_options;
  echo_options.title = "Echo delay over time";
  echo_options.x_label = "time since start, s";
  echo_options.y_label = "echo delay, µs (log)";
  echo_options.log_y = true;

  std::vector<XySeries> latency_series{{result.client.name, "#1f77b4", to_points(result.client.latency_series_ms), false}};
  std::vector<XyPoint> rate;
  for (std::size_t index = 1; index < result.client.response_times_s.size(); ++index) {
    const double gap_ms = 1e3 * (result.client.response_times_s[index] - result.client.response_times_s[index - 1]);
    rate.push_back({result.client.response_times_s[index], gap_ms});
  }
  ChartOptions latency_options;
  latency_options.title = "Measured OCP latency (latency_ms, per control tick)";
  latency_options.x_label = "time since start, s";
  latency_options.y_label = "latency, ms";
  ChartOptions gap_options;
  gap_options.title = "Gap between consecutive responses";
  gap_options.x_label = "time since start, s";
  gap_options.y_label = "gap, ms";

  std::string html =
      "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>ocp_bench loop</title>\n"
      "<style>body{font-family:sans-serif;margin:20px}pre{background:#f6f6f6;padding:8px}</style></head><body>\n"
      "<h1>ocp_bench loop</h1>\n<pre>";
  std::ostringstream table;
  print_table(table, result);
  for (const char c : table.str()) {
    if (c == '<') html += "&lt;";
    else if (c == '>') html += "&gt;";
    else if (c == '&') html += "&amp;";
    else html += c;
  }
  html += "</pre>\n";
  html += log_histogram(histogram, histogram_options);
  html += xy_chart(echo_series, echo_options);
  html += xy_chart(latency_series, latency_options);
  html += xy_chart({{"response gap", "#9467bd", rate, true}}, gap_options);
  return html + "</body></html>\n";
}

}  // namespace ocp::bench
