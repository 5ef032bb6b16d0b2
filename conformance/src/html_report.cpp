// A single self-contained HTML file (inline CSS, no scripts, no external resources): the case
// matrix on top, then one section per case; the wire log for every case that is not OK.
#include <fmt/format.h>

#include <cstdint>
#include <set>
#include <utility>

#include "conformance/reports.hpp"
#include "ocp/build_info.hpp"
#include "sim_app/report_text.hpp"

namespace ocp::conformance {
namespace {

using report::clip;
using report::markup_escape;

constexpr const char* style = R"(
body{font-family:system-ui,sans-serif;margin:2em;color:#222}
table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #ccc;padding:4px 8px;text-align:left;vertical-align:top}
.ok{background:#d9f2d9}.non-strict{background:#fff2c6}.informational{background:#dde8f8}.failed{background:#f8d0d0}
pre{white-space:pre-wrap;word-break:break-all;margin:0;font-size:12px}
.wire td{font-family:monospace;font-size:12px}.out{color:#064}.in{color:#036}.note{color:#777}
.altered{background:#f8d0d0;font-weight:bold}
section{border-top:1px solid #aaa;margin-top:2em}
)";

// On the vehicle wire each control frame carries one pair, so a response whose pair no control
// frame carried is altered: its row is highlighted (the operator wire's frames carry a pair per
// vehicle, and the case text lists what was altered there).
std::string wire_rows(const CaseResult& result, bool highlight_altered) {
  std::set<std::pair<std::uint64_t, std::uint32_t>> sent;
  for (const WireLogEntry& e : result.wire_log) {
    if (e.kind == WireEntryKind::out && e.ack) sent.emplace(e.ack->ack_time, e.ack->ack_time_mac);
  }
  std::string rows;
  const std::size_t n = result.wire_log.size();
  const std::int64_t origin = n == 0 ? 0 : result.wire_log.front().time_us;
  for (std::size_t i = 0; i < n; ++i) {
    if (i >= wire_log_head && i + wire_log_tail < n) {
      if (i == wire_log_head)
        rows += fmt::format("<tr><td colspan=5>… {} entries elided …</td></tr>\n", n - wire_log_head - wire_log_tail);
      continue;
    }
    const WireLogEntry& e = result.wire_log[i];
    const std::string kind(wire_entry_kind_name(e.kind));
    const std::string length = (e.kind == WireEntryKind::out || e.kind == WireEntryKind::in)
                                   ? fmt::format("{}{}", e.length_prefix, e.drained ? " (drained)" : "")
                                   : "";
    const std::string pair = e.ack ? fmt::format("{} / {}", e.ack->ack_time, e.ack->ack_time_mac) : "";
    const bool altered = highlight_altered && e.kind == WireEntryKind::in && e.ack &&
                         !sent.contains({e.ack->ack_time, e.ack->ack_time_mac});
    rows += fmt::format(
        "<tr class=\"{}\"><td>{:.3f}</td><td>{}</td><td>{}</td><td>{}</td><td><pre>{}</pre></td></tr>\n",
        altered                         ? "in altered"
        : kind == "out" || kind == "in" ? kind
                                        : "note",
        static_cast<double>(e.time_us - origin) / 1000.0, kind, length, pair, markup_escape(clip(e.text, 600)));
  }
  return rows;
}

}  // namespace

std::string html_report(const ReportContext& report) {
  const RunSummary& summary = *report.summary;
  std::string html = fmt::format(
      "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>OCP conformance: "
      "{}</title><style>{}</style></head><body>\n",
      report.suite, style);
  html += fmt::format(
      "<h1>OCP conformance — {} side</h1>\n<p>Client: <code>{}</code><br>{}; exit code {}<br>ocp_conformance {}</p>\n",
      report.suite, markup_escape(report.client), markup_escape(verdict_counts(summary)),
      run_exit_code(summary, nullptr), markup_escape(build_info::version_line()));
  for (const NamedCause& cause : named_causes(summary)) {
    std::string ids;
    for (const std::string& id : cause.case_ids) ids += (ids.empty() ? "" : ", ") + id;
    html += "<p class=\"failed\"><b>Cause found</b>: " + markup_escape(cause.cause) + " (in " + markup_escape(ids) +
            ")</p>\n";
  }
  if (summary.interrupted)
    html += "<p class=\"failed\"><b>Interrupted</b> (Ctrl-C): " + markup_escape(interrupted_text(summary)) + "</p>\n";
  if (!summary.harness_error.empty())
    html += "<p class=\"failed\">Harness error: " + markup_escape(summary.harness_error) + "</p>\n";
  html += "<table><tr><th>case</th><th>tier</th><th>verdict</th><th>ms</th><th>title</th></tr>\n";
  for (const CaseResult& result : summary.results) {
    html += fmt::format(
        "<tr class=\"{}\"><td><a href=\"#{}\">{}</a></td><td>{}</td><td>{}</td><td>{:.0f}</td><td>{}</td></tr>\n",
        verdict_slug(result.verdict), markup_escape(result.info.id), markup_escape(result.info.id),
        tier_name(result.info.tier), verdict_name(result.verdict), result.duration_ms,
        markup_escape(result.info.title));
  }
  html += "</table>\n";
  for (const CaseResult& result : summary.results) {
    html += fmt::format("<section id=\"{}\"><h2 class=\"{}\">{} — {} ({})</h2>\n", markup_escape(result.info.id),
                        verdict_slug(result.verdict), markup_escape(result.info.id), verdict_name(result.verdict),
                        tier_name(result.info.tier));
    html += "<p><b>" + markup_escape(result.info.title) + "</b></p>\n";
    html += "<p><b>Requirement</b> (" + markup_escape(result.info.source) +
            "): " + markup_escape(result.info.requirement) + "</p>\n<p><b>Expected</b></p><ul>";
    for (const std::string& e : result.info.expected) html += "<li>" + markup_escape(e) + "</li>";
    html += "</ul>\n<p><b>Actual</b>: " + markup_escape(result.actual) +
            fmt::format(" ({:.0f} ms)</p>\n", result.duration_ms);
    if (!result.wire_log.empty()) {
      html += fmt::format(
          "<details{}><summary>Wire log ({} entries)</summary><table "
          "class=\"wire\"><tr><th>ms</th><th>dir</th><th>length prefix</th><th>ack_time / "
          "mac</th><th>payload</th></tr>\n",
          result.verdict == Verdict::failed ? " open" : "", result.wire_log.size());
      html += wire_rows(result, report.suite == "vehicle") + "</table></details>\n";
    }
    html += "</section>\n";
  }
  html += "</body></html>\n";
  return html;
}

}  // namespace ocp::conformance
