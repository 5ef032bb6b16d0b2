// summary.json, its reader and merge (results.hpp).
#include <rapidjson/document.h>

#include <algorithm>
#include <map>
#include <set>
#include <sstream>

#include "campaign/results.hpp"
#include "ocp/build_info.hpp"
#include "sim_app/report_text.hpp"

namespace ocp::campaign {

namespace {
constexpr std::size_t violations_per_world = 5;

std::string json_string(const std::string& text) { return "\"" + report::json_escape(text) + "\""; }

std::string json_strings(const std::vector<std::string>& texts) {
  std::string out = "[";
  for (std::size_t k = 0; k < texts.size(); ++k) out += (k == 0 ? "" : ", ") + json_string(texts[k]);
  return out + "]";
}

std::vector<std::string> strings_of(const rapidjson::Value& item, const char* key) {
  std::vector<std::string> out;
  if (item.HasMember(key)) {
    for (const auto& text : item[key].GetArray()) out.emplace_back(text.GetString());
  }
  return out;
}
}  // namespace

Summary summarise(const CampaignOptions& options, const CampaignRun& run) {
  Summary summary;
  summary.seed = options.seed;
  summary.profile = options.profile.name;
  summary.profile_digest = options.profile.digest;
  summary.worlds = options.worlds;
  summary.shard = options.shard;
  summary.interrupted = run.interrupted;
  summary.client_worlds = options.client.has_value();
  summary.client_real_time = options.client && options.client->time == ClientTime::real_time;
  for (const WorldOutcome& outcome : run.outcomes) {
    WorldRecord record;
    record.index = outcome.index;
    record.seed = outcome.seed;
    record.duration_us = outcome.duration.count();
    record.vehicles = outcome.vehicles;
    record.timeline_events = outcome.timeline_events;
    record.determinism_checked = outcome.determinism_checked;
    record.liveness_checked = outcome.liveness_checked;
    record.violation_count = outcome.violation_count;
    record.error = outcome.error;
    record.hazards = outcome.hazards;
    for (const Violation& violation : outcome.violations) {
      if (record.violations.size() >= violations_per_world) break;
      record.violations.push_back({std::string(check_name(violation.check)), violation.at.count(), violation.vehicle,
                                   violation.detail});
    }
    summary.records.push_back(std::move(record));
  }
  std::sort(summary.records.begin(), summary.records.end(),
            [](const WorldRecord& a, const WorldRecord& b) { return a.index < b.index; });
  return summary;
}

std::string summary_json(const Summary& s) {
  std::ostringstream out;
  std::uint64_t failures = 0;
  std::map<std::string, std::uint64_t> by_check;
  for (const WorldRecord& r : s.records) {
    if (!r.failed()) continue;
    ++failures;
    std::set<std::string> checks;
    for (const ViolationRecord& v : r.violations) checks.insert(v.check);
    if (!r.error.empty()) checks.insert("world_refused_to_start");
    for (const std::string& check : checks) ++by_check[check];
  }
  out << "{\n  \"campaign_seed\": " << s.seed << ",\n  \"ocp_sim_version\": " << json_string(build_info::version_line())
      << ",\n  \"profile\": " << json_string(s.profile)
      << ",\n  \"profile_digest\": " << s.profile_digest << ",\n  \"worlds\": " << s.worlds
      << ",\n  \"shard\": {\"index\": " << s.shard.index << ", \"count\": " << s.shard.count << "}"
      << ",\n  \"interrupted\": " << (s.interrupted ? "true" : "false")
      << ",\n  \"client_worlds\": " << (s.client_worlds ? "true" : "false");
  if (s.client_worlds) out << ",\n  \"client_time\": " << (s.client_real_time ? "\"real\"" : "\"virtual\"");
  out << ",\n  \"worlds_run\": " << s.records.size()
      << ",\n  \"failures\": " << failures << ",\n  \"failures_by_check\": {";
  bool first = true;
  for (const auto& [check, count] : by_check) {
    out << (first ? "" : ", ") << json_string(check) << ": " << count;
    first = false;
  }
  out << "},\n  \"results\": [";
  for (std::size_t i = 0; i < s.records.size(); ++i) {
    const WorldRecord& r = s.records[i];
    out << (i == 0 ? "\n" : ",\n") << "    {\"index\": " << r.index << ", \"seed\": " << r.seed
        << ", \"duration_us\": " << r.duration_us << ", \"vehicles\": " << r.vehicles
        << ", \"timeline_events\": " << r.timeline_events
        << ", \"determinism_checked\": " << (r.determinism_checked ? "true" : "false")
        << ", \"liveness_checked\": " << (r.liveness_checked ? "true" : "false")
        << ", \"violation_count\": " << r.violation_count;
    if (s.client_worlds) out << ", \"hazards\": " << json_strings(r.hazards);
    if (!r.error.empty()) out << ", \"error\": " << json_string(r.error);
    if (r.failed()) {
      out << ", \"failure_dir\": " << json_string(r.failure_dir()) << ", \"files\": " << json_strings(r.files)
          << ", \"replay\": " << json_string(r.replay);
    }
    out << ", \"violations\": [";
    for (std::size_t k = 0; k < r.violations.size(); ++k) {
      const ViolationRecord& v = r.violations[k];
      out << (k == 0 ? "" : ", ") << "{\"check\": " << json_string(v.check) << ", \"at_us\": " << v.at_us
          << ", \"vehicle\": " << json_string(v.vehicle) << ", \"detail\": " << json_string(v.detail) << "}";
    }
    out << "]}";
  }
  out << "\n  ]\n}\n";
  return out.str();
}

Summary read_summary_json(const std::string& text, const std::string& path) {
  rapidjson::Document d;
  d.Parse(text.c_str(), text.size());
  auto fail = [&](const std::string& why) -> MergeError { return MergeError(path + ": " + why); };
  if (d.HasParseError() || !d.IsObject()) throw fail("not a campaign summary.json (not a JSON object)");
  for (const char* key : {"campaign_seed", "profile", "profile_digest", "worlds", "shard", "interrupted", "results"}) {
    if (!d.HasMember(key)) throw fail(std::string("not a campaign summary.json (no '") + key + "')");
  }
  Summary s;
  try {
    s.seed = d["campaign_seed"].GetUint64();
    s.profile = d["profile"].GetString();
    s.profile_digest = d["profile_digest"].GetUint64();
    s.worlds = d["worlds"].GetUint64();
    s.shard.index = d["shard"]["index"].GetUint();
    s.shard.count = d["shard"]["count"].GetUint();
    s.interrupted = d["interrupted"].GetBool();
    s.client_worlds = d.HasMember("client_worlds") && d["client_worlds"].GetBool();
    // Without the field (a summary from before virtual time): real time, as client worlds were.
    s.client_real_time = s.client_worlds && !(d.HasMember("client_time") && d["client_time"].IsString() &&
                                              std::string_view(d["client_time"].GetString()) == "virtual");
    for (const auto& item : d["results"].GetArray()) {
      WorldRecord r;
      r.index = item["index"].GetUint64();
      r.seed = item["seed"].GetUint64();
      r.duration_us = item["duration_us"].GetInt64();
      r.vehicles = item["vehicles"].GetInt();
      r.timeline_events = item["timeline_events"].GetInt();
      r.determinism_checked = item["determinism_checked"].GetBool();
      r.liveness_checked = item["liveness_checked"].GetBool();
      r.violation_count = item["violation_count"].GetUint64();
      if (item.HasMember("error")) r.error = item["error"].GetString();
      r.files = strings_of(item, "files");
      r.hazards = strings_of(item, "hazards");
      if (item.HasMember("replay")) r.replay = item["replay"].GetString();
      for (const auto& v : item["violations"].GetArray()) {
        r.violations.push_back({v["check"].GetString(), v["at_us"].GetInt64(), v["vehicle"].GetString(), v["detail"].GetString()});
      }
      s.records.push_back(std::move(r));
    }
  } catch (...) {
    throw fail("a field has the wrong type");
  }
  return s;
}

Summary merge_summaries(const std::vector<Summary>& shards) {
  if (shards.empty()) throw MergeError("no shards to merge");
  const Summary& first = shards.front();
  Summary merged;
  merged.seed = first.seed;
  merged.profile = first.profile;
  merged.profile_digest = first.profile_digest;
  merged.worlds = first.worlds;
  merged.client_worlds = first.client_worlds;
  merged.client_real_time = first.client_real_time;
  std::set<std::uint32_t> seen;
  for (const Summary& shard : shards) {
    if (shard.seed != first.seed || shard.profile_digest != first.profile_digest || shard.worlds != first.worlds ||
        shard.shard.count != first.shard.count) {
      throw MergeError("shard " + std::to_string(shard.shard.index) + "/" + std::to_string(shard.shard.count) +
                       " belongs to another campaign (seed " + std::to_string(shard.seed) + ", profile " + shard.profile +
                       ", " + std::to_string(shard.worlds) + " worlds; expected seed " + std::to_string(first.seed) +
                       ", profile " + first.profile + ", " + std::to_string(first.worlds) + " worlds)");
    }
    if (!seen.insert(shard.shard.index).second) {
      throw MergeError("shard " + std::to_string(shard.shard.index) + "/" + std::to_string(shard.shard.count) + " given twice");
    }
    merged.interrupted = merged.interrupted || shard.interrupted;
    merged.records.insert(merged.records.end(), shard.records.begin(), shard.records.end());
  }
  // Missing shards leave worlds out: say so as an interrupted campaign would.
  if (seen.size() != first.shard.count) merged.interrupted = true;
  std::sort(merged.records.begin(), merged.records.end(),
            [](const WorldRecord& a, const WorldRecord& b) { return a.index < b.index; });
  return merged;
}

}  // namespace ocp::campaign
