// JUnit, the HTML index and the terminal table of a campaign (results.hpp).
#include <algorithm>
#include <map>
#include <sstream>

#include "campaign/results.hpp"
#include "ocp/build_info.hpp"

namespace ocp::campaign {

namespace {

std::string escape_xml(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '&': out += "&amp;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string first_line(const WorldRecord& r) {
  if (!r.error.empty()) return "world refused to start: " + r.error;
  if (r.violations.empty()) return std::to_string(r.violation_count) + " violations";
  const ViolationRecord& v = r.violations.front();
  return v.check + " at " + std::to_string(v.at_us) + " us" + (v.vehicle.empty() ? "" : " on " + v.vehicle) + ": " + v.detail;
}

std::uint64_t failures(const Summary& s) {
  std::uint64_t count = 0;
  for (const WorldRecord& r : s.records) count += r.failed() ? 1 : 0;
  return count;
}

}  // namespace

std::string junit_xml(const Summary& s) {
  std::ostringstream out;
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites>\n  <testsuite name=\"campaign-" << s.seed << "-"
      << escape_xml(s.profile) << "\" tests=\"" << s.records.size() << "\" failures=\"" << failures(s) << "\">\n";
  out << "    <properties><property name=\"ocp_sim_version\" value=\"" << escape_xml(build_info::version_line())
      << "\"/></properties>\n";
  for (const WorldRecord& r : s.records) {
    out << "    <testcase classname=\"campaign\" name=\"world-" << r.index << "\" time=\"0\"";
    if (!r.failed()) {
      out << "/>\n";
      continue;
    }
    out << ">\n      <failure message=\"" << escape_xml(first_line(r)) << "\">";
    for (const ViolationRecord& v : r.violations) {
      out << escape_xml(v.check + " at " + std::to_string(v.at_us) + " us " + v.vehicle + ": " + v.detail) << "\n";
    }
    out << "see " << r.failure_dir() << "</failure>\n    </testcase>\n";
  }
  out << "  </testsuite>\n</testsuites>\n";
  return out.str();
}

std::string html_index(const Summary& s) {
  std::ostringstream out;
  out << "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>campaign " << s.seed << "</title>\n"
      << "<style>body{font-family:sans-serif}td,th{padding:2px 8px;text-align:left}.fail{color:#b00}</style></head>\n"
      << "<body><h1>Campaign " << s.seed << ", profile " << escape_xml(s.profile) << "</h1>\n<p>" << s.records.size()
      << " of " << s.worlds << " worlds run, " << failures(s) << " failed" << (s.interrupted ? " (interrupted)" : "")
      << ".</p>\n";
  out << "<table><tr><th>world</th><th>seed</th><th>first violation</th><th>files</th></tr>\n";
  for (const WorldRecord& r : s.records) {
    if (!r.failed()) continue;
    out << "<tr class=\"fail\"><td>" << r.index << "</td><td>" << r.seed << "</td><td>" << escape_xml(first_line(r))
        << "</td><td>";
    // Only the files the world's folder got (a client world is not shrunk: no report.html).
    for (std::size_t k = 0; k < r.files.size(); ++k) {
      const std::string path = r.failure_dir() + "/" + r.files[k];
      out << (k == 0 ? "" : " · ") << "<a href=\"" << escape_xml(path) << "\">" << escape_xml(r.files[k]) << "</a>";
    }
    if (!r.replay.empty()) out << "<br><code>" << escape_xml(r.replay) << "</code>";
    out << "</td></tr>\n";
  }
  out << "</table></body></html>\n";
  return out.str();
}

namespace {
constexpr std::size_t failing_worlds_listed = 10;

// What the client worlds put the client through: in how many worlds each hazard came.
void client_hazards(std::ostringstream& out, const Summary& s) {
  std::map<std::string, std::size_t> worlds;
  for (const WorldRecord& r : s.records) {
    for (const std::string& hazard : r.hazards) ++worlds[hazard];
  }
  out << "  client hazards (worlds of " << s.records.size() << "):";
  if (worlds.empty()) out << " none";
  for (const auto& [hazard, count] : worlds) out << " " << hazard << " " << count;
  out << "\n";
}

// Each failing world's first violation and replay command (the first ten, then a count).
void failing_worlds(std::ostringstream& out, const Summary& s) {
  std::size_t listed = 0, failing = 0;
  for (const WorldRecord& r : s.records) {
    if (!r.failed()) continue;
    if (++failing > failing_worlds_listed) continue;
    ++listed;
    out << "  ✗ world " << r.index << ": " << first_line(r) << "\n";
    if (!r.replay.empty()) out << "      replay: " << r.replay << "\n";
    if (!r.files.empty()) {
      out << "      files:  " << r.failure_dir() << "/";
      for (std::size_t k = 0; k < r.files.size(); ++k) out << (k == 0 ? "" : ", ") << r.files[k];
      out << "\n";
    }
  }
  if (failing > listed) out << "  … and " << failing - listed << " more failing worlds (summary.json)\n";
}
}  // namespace

std::string summary_table(const Summary& s) {
  std::map<std::string, std::uint64_t> by_check;
  double simulated = 0;
  for (const WorldRecord& r : s.records) {
    simulated += static_cast<double>(r.duration_us) / 1e6;
    if (!r.error.empty()) ++by_check["world_refused_to_start"];
    std::map<std::string, bool> seen;
    for (const ViolationRecord& v : r.violations) {
      if (!seen[v.check]) ++by_check[v.check];
      seen[v.check] = true;
    }
  }
  std::ostringstream out;
  out << "campaign " << s.seed << ", profile " << s.profile << ": " << s.records.size() << " of " << s.worlds
      << " worlds, " << static_cast<std::uint64_t>(simulated) << " s simulated, " << failures(s) << " failed\n";
  out << "     check                     worlds failing\n";
  // Every check, then any other name that failed (from a summary of another version).
  std::vector<std::pair<std::string, std::string_view>> rows;   // name, why not judged
  for (int c = 0; c < check_count; ++c) {
    const auto check = static_cast<Check>(c);
    rows.emplace_back(std::string(check_name(check)), not_judged_because(check, s.client_worlds, s.client_real_time));
  }
  rows.emplace_back("world_refused_to_start", "");
  for (const auto& [check, count] : by_check) {
    if (std::none_of(rows.begin(), rows.end(), [&](const auto& row) { return row.first == check; })) rows.emplace_back(check, "");
  }
  for (const auto& [check, why] : rows) {
    const std::uint64_t count = by_check[check];
    // A check not judged shows its reason, never a 0 that reads as "passed".
    const std::string mark = count > 0 ? "✗" : why.empty() ? "✓" : "—";
    const std::string result = count > 0 || why.empty() ? std::to_string(count) : "— (" + std::string(why) + ")";
    char line[160];
    std::snprintf(line, sizeof line, "  %s  %-25s %s\n", mark.c_str(), check.c_str(), result.c_str());
    out << line;
  }
  if (s.client_worlds) client_hazards(out, s);
  failing_worlds(out, s);
  return out.str();
}

}  // namespace ocp::campaign
