#include <fmt/format.h>

#include "conformance/reports.hpp"
#include "ocp/build_info.hpp"
#include "sim_app/report_text.hpp"

namespace ocp::conformance {
namespace {

using report::clip;
using report::json_escape;

std::string entry_json(const WireLogEntry& e, std::int64_t origin_us) {
  std::string out = fmt::format(R"({{"t_ms":{:.3f},"kind":"{}")", static_cast<double>(e.time_us - origin_us) / 1000.0,
                                wire_entry_kind_name(e.kind));
  if (e.kind == WireEntryKind::out || e.kind == WireEntryKind::in) {
    out += fmt::format(R"(,"length_prefix":{},"drained":{})", e.length_prefix, e.drained ? "true" : "false");
  }
  if (e.ack) out += fmt::format(R"(,"ack_time":{},"ack_time_mac":{})", e.ack->ack_time, e.ack->ack_time_mac);
  if (!e.close_code.empty()) out += fmt::format(R"(,"close_code":"{}")", json_escape(e.close_code));
  out += fmt::format(R"(,"text":"{}"}})", json_escape(clip(e.text)));
  return out;
}

}  // namespace

std::string index_json(const ReportContext& report) {
  const RunSummary& summary = *report.summary;
  std::string out = fmt::format(
      R"({{"suite":"{}","ocp_sim_version":"{}","client":"{}","duration_ms":{:.1f},"exit_code":{},"harness_error":"{}","interrupted":{},"cases":[)",
      report.suite, json_escape(build_info::version_line()), json_escape(report.client), summary.duration_ms,
      run_exit_code(summary, nullptr), json_escape(summary.harness_error), summary.interrupted);
  bool first = true;
  for (const CaseResult& result : summary.results) {
    out += first ? "\n" : ",\n";
    first = false;
    out += fmt::format(
        R"({{"id":"{}","title":"{}","tier":"{}","verdict":"{}","duration_ms":{:.1f},"source":"{}","requirement":"{}","expected":[)",
        json_escape(result.info.id), json_escape(result.info.title), tier_name(result.info.tier),
        verdict_name(result.verdict), result.duration_ms, json_escape(result.info.source),
        json_escape(result.info.requirement));
    for (std::size_t i = 0; i < result.info.expected.size(); ++i) {
      out += i ? "," : "";
      out += fmt::format(R"("{}")", json_escape(result.info.expected[i]));
    }
    out += fmt::format(R"(],"actual":"{}","cause":"{}","client_log":"{}","wire_log":[)", json_escape(result.actual),
                       json_escape(result.cause), json_escape(result.client_log_path));
    const std::int64_t origin = result.wire_log.empty() ? 0 : result.wire_log.front().time_us;
    const std::size_t n = result.wire_log.size();
    bool any = false;
    for (std::size_t i = 0; i < n; ++i) {
      if (i >= wire_log_head && i + wire_log_tail < n) {
        if (i == wire_log_head) {
          out += fmt::format(R"({}{{"kind":"elided","count":{}}})", any ? "," : "", n - wire_log_head - wire_log_tail);
          any = true;
        }
        continue;
      }
      out += any ? "," : "";
      out += entry_json(result.wire_log[i], origin);
      any = true;
    }
    out += "]}";
  }
  out += "\n]";
  if (report.baseline != nullptr) {
    auto list = [](const std::vector<std::string>& ids) {
      std::string text = "[";
      for (std::size_t i = 0; i < ids.size(); ++i) {
        text += i ? "," : "";
        text += fmt::format(R"("{}")", json_escape(ids[i]));
      }
      return text + "]";
    };
    out += fmt::format(R"(,"baseline":{{"new_failures":{},"still_failing":{},"fixed":{}}})",
                       list(report.baseline->new_failures), list(report.baseline->still_failing),
                       list(report.baseline->fixed));
  }
  out += "}\n";
  return out;
}

}  // namespace ocp::conformance
