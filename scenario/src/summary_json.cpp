// summary.json (reports.hpp): latency percentiles, fault intervals per side, messages per
// direction, the timeline as it ran, the verdicts, the seed and the reproduce command.
#include <rapidjson/prettywriter.h>
#include <rapidjson/stringbuffer.h>

#include "ocp/build_info.hpp"
#include "scenario/metrics.hpp"
#include "scenario/reports.hpp"

namespace ocp::scenario {
namespace {

using Json = rapidjson::PrettyWriter<rapidjson::StringBuffer>;

void key(Json& json, std::string_view name) { json.Key(name.data(), static_cast<rapidjson::SizeType>(name.size())); }
void text(Json& json, std::string_view name, std::string_view value) {
  key(json, name);
  json.String(value.data(), static_cast<rapidjson::SizeType>(value.size()));
}
double seconds(SimTime time) { return static_cast<double>(time.count()) / 1e6; }

void latency(Json& json, const ValueHistogram& values) {
  json.StartObject();
  key(json, "count");
  json.Uint64(values.count());
  for (const auto& [name, p] : {std::pair{"p50", 50.0}, std::pair{"p95", 95.0}, std::pair{"p99", 99.0}}) {
    key(json, name);
    if (auto v = aggregate(values, "p", p)) json.Double(*v); else json.Null();
  }
  key(json, "max");
  if (auto v = aggregate(values, "max", 0)) json.Double(*v); else json.Null();
  json.EndObject();
}

void route(Json& json, const RouteCounters& counters) {
  json.StartObject();
  key(json, "sent"); json.Uint64(counters.sent);
  key(json, "delivered"); json.Uint64(counters.delivered);
  key(json, "lost"); json.Uint64(counters.dropped);
  json.EndObject();
}

// Overall latency, per vehicle, and the Player's ping.
void latency_section(Json& json, const Observations& obs) {
  key(json, "latency_ms");
  latency(json, series_values(obs, "latency_ms", std::nullopt));
  key(json, "latency_ms_per_vehicle");
  json.StartObject();
  for (const auto& [name, data] : obs.vehicles) {
    key(json, name);
    latency(json, series_values(obs, "latency_ms", name));
  }
  json.EndObject();

  key(json, "ping_ms");   // sampled every 100 ms from the Player's feedback (plot only)
  ValueHistogram pings;
  for (const auto& [name, data] : obs.vehicles) pings.merge(data.ping_ms.values());
  latency(json, pings);
}

void faults_section(Json& json, const Observations& obs) {
  key(json, "faults");
  json.StartArray();
  for (const auto& [fault_key, list] : obs.faults) {
    json.StartObject();
    text(json, "vehicle", fault_key.first);
    text(json, "fault", fault_identifier(fault_key.second));
    text(json, "side", fault_side_name(fault_side(fault_key.second)));
    key(json, "intervals_s");
    json.StartArray();
    for (const Interval& interval : list) {
      json.StartArray();
      json.Double(seconds(interval.start));
      if (interval.end) json.Double(seconds(*interval.end)); else json.Null();
      json.EndArray();
    }
    json.EndArray();
    json.EndObject();
  }
  json.EndArray();
}

// Totals per direction over every vehicle, then each vehicle's.
void messages_section(Json& json, const Observations& obs) {
  RouteCounters to_streamer, to_player;
  for (const auto& [name, data] : obs.vehicles) {
    to_streamer.sent += data.to_streamer.sent;
    to_streamer.delivered += data.to_streamer.delivered;
    to_streamer.dropped += data.to_streamer.dropped;
    to_player.sent += data.to_player.sent;
    to_player.delivered += data.to_player.delivered;
    to_player.dropped += data.to_player.dropped;
  }
  key(json, "messages");
  json.StartObject();
  key(json, "to_streamer"); route(json, to_streamer);
  key(json, "to_player"); route(json, to_player);
  key(json, "per_vehicle");
  json.StartObject();
  for (const auto& [name, data] : obs.vehicles) {
    key(json, name);
    json.StartObject();
    key(json, "to_streamer"); route(json, data.to_streamer);
    key(json, "to_player"); route(json, data.to_player);
    json.EndObject();
  }
  json.EndObject();
  json.EndObject();
}

void timeline_section(Json& json, const std::vector<FiredEvent>& fired) {
  key(json, "timeline");
  json.StartArray();
  for (const FiredEvent& event : fired) {
    json.StartObject();
    key(json, "t_s"); json.Double(seconds(event.at));
    text(json, "name", event.name);
    text(json, "label", event.label);
    json.EndObject();
  }
  json.EndArray();
}

void verdicts_section(Json& json, const std::vector<Verdict>& verdicts) {
  key(json, "verdicts");
  json.StartArray();
  for (const Verdict& verdict : verdicts) {
    json.StartObject();
    text(json, "title", verdict.title);
    text(json, "kind", verdict.kind);
    key(json, "line"); json.Int(verdict.mark.line);
    key(json, "passed"); json.Bool(verdict.passed);
    key(json, "interrupted"); json.Bool(verdict.interrupted);
    text(json, "expected", verdict.expected);
    text(json, "actual", verdict.actual);
    json.EndObject();
  }
  json.EndArray();
}

}  // namespace

std::string summary_json(const RunReport& report) {
  const Scenario& scenario = *report.scenario;
  const RunResult& run = *report.run;
  rapidjson::StringBuffer buffer;
  Json json(buffer);
  json.SetIndent(' ', 1);
  json.StartObject();
  text(json, "scenario", scenario.name);
  text(json, "file", scenario.path);
  text(json, "ocp_sim_version", build_info::version_line());   // the tool that gave the verdicts
  key(json, "seed"); json.Uint64(run.seed);
  key(json, "duration_s"); json.Double(seconds(run.duration));
  text(json, "reproduce", report.reproduce);
  key(json, "passed"); json.Bool(all_passed(report.verdicts) && !run.interrupted);
  // Ctrl-C: the run stopped at ran_s; verdicts that needed the rest say "interrupted".
  key(json, "interrupted"); json.Bool(run.interrupted);
  key(json, "ran_s"); json.Double(seconds(run.ran));
  latency_section(json, run.observations);
  faults_section(json, run.observations);
  messages_section(json, run.observations);
  timeline_section(json, run.fired);
  verdicts_section(json, report.verdicts);
  key(json, "trace");
  json.StartObject();
  key(json, "lines"); json.Uint64(run.trace_lines);
  key(json, "digest"); json.Uint64(run.trace_digest);
  json.EndObject();
  key(json, "wall_s"); json.Double(run.wall_seconds);
  json.EndObject();
  return std::string(buffer.GetString(), buffer.GetSize()) + "\n";
}

}  // namespace ocp::scenario
