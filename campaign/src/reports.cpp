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
    const std::string dir = r.failure_dir();
    out << "<tr class=\"fail\"><td>" << r.index << "</td><td>" << r.seed << "</td><td>" << escape_xml(first_line(r))
        << "</td><td><a href=\"" << dir << "/report.html\">report.html</a> · <a href=\"" << dir
        << "/shrunk.yaml\">shrunk.yaml</a> · <a href=\"" << dir << "/world.yaml\">world.yaml</a></td></tr>\n";
  }
  out << "</table></body></html>\n";
  return out.str();
}

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
  out << "  check                     worlds failing\n";
  // Every oracle check, then any other that failed (the client.* checks of a --client campaign).
  std::vector<std::string> rows;
  for (int c = 0; c < check_count; ++c) {
    const auto check = static_cast<Check>(c);
    if (check != Check::client_echo && check != Check::client_reconnect && check != Check::client_alive) {
      rows.emplace_back(check_name(check));
    }
  }
  rows.emplace_back("world_refused_to_start");
  for (const auto& [check, count] : by_check) {
    if (std::find(rows.begin(), rows.end(), check) == rows.end()) rows.push_back(check);
  }
  for (const std::string& check : rows) {
    char line[80];
    std::snprintf(line, sizeof line, "  %-25s %llu\n", check.c_str(), static_cast<unsigned long long>(by_check[check]));
    out << line;
  }
  return out.str();
}

}  // namespace ocp::campaign
