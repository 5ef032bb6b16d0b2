// The text form of a trace, rendered from its JSON Lines (docs/trace-format.md): one line per
// event, "<time µs, 12 wide> <source> <what happened>", for people reading a run.
#include <rapidjson/document.h>

#include <fmt/format.h>

#include <string>

#include "world/trace.hpp"

namespace ocp {
namespace {

using Json = rapidjson::Value;

std::string_view str(const Json& line, const char* name) {
  const auto found = line.FindMember(name);
  if (found == line.MemberEnd() || !found->value.IsString()) return "?";
  return {found->value.GetString(), found->value.GetStringLength()};
}

std::string num(const Json& line, const char* name) {
  const auto found = line.FindMember(name);
  if (found == line.MemberEnd() || found->value.IsNull()) return "none";
  if (found->value.IsUint64()) return std::to_string(found->value.GetUint64());
  if (found->value.IsInt64()) return std::to_string(found->value.GetInt64());
  if (found->value.IsNumber()) return fmt::format("{}", found->value.GetDouble());
  return "?";
}

bool truth(const Json& line, const char* name) {
  const auto found = line.FindMember(name);
  return found != line.MemberEnd() && found->value.IsBool() && found->value.GetBool();
}

bool has(const Json& line, const char* name) { return line.HasMember(name); }

std::string describe(const Json& line) {
  const std::string_view event = str(line, "event");
  if (event == "frame") {
    std::string out = fmt::format("frame {} {} {} len={}", str(line, "dir"), str(line, "wire"),
                                  str(line, "kind"), num(line, "len"));
    if (has(line, "ack_time")) out += fmt::format(" ack={}/{}", num(line, "ack_time"), num(line, "ack_time_mac"));
    if (truth(line, "drained")) out += " drained";
    return out;
  }
  if (event == "fault") {
    return fmt::format("fault {} {} ({} side, {})", str(line, "fault"),
                       truth(line, "active") ? "raised" : "cleared", str(line, "side"),
                       str(line, "vehicle"));
  }
  if (event == "connection") {
    std::string out = fmt::format("{} connection {} {}", str(line, "wire"), str(line, "change"),
                                  str(line, "peer"));
    if (has(line, "reason")) out += fmt::format(": {} ({})", str(line, "reason"), str(line, "detail"));
    return out;
  }
  if (event == "latency") {
    return fmt::format("latency {} ms, newest pair {} us old, tick +{} us{}", num(line, "latency_ms"),
                       num(line, "pair_age_us"), num(line, "tick_lateness_us"),
                       truth(line, "control_sent") ? ", control sent" : "");
  }
  if (event == "link") {
    std::string out = fmt::format("link {} {} {} #{} {} B", str(line, "route"), str(line, "outcome"),
                                  str(line, "kind"), num(line, "id"), num(line, "bytes"));
    if (has(line, "reason")) out += fmt::format(" ({})", str(line, "reason"));
    return out;
  }
  if (event == "impairments") {
    return fmt::format("impairments {}: delay {} us, jitter {} {} us, loss {}, burst {}, bandwidth {} bit/s, "
                       "duplicate {}, reorder {}{}",
                       str(line, "route"), num(line, "delay_us"), str(line, "jitter_kind"),
                       num(line, "jitter_us"), num(line, "loss"), truth(line, "burst_loss") ? "on" : "off",
                       num(line, "bandwidth_bps"), num(line, "duplicate"), num(line, "reorder"),
                       truth(line, "down") ? ", DOWN" : "");
  }
  if (event == "gamepad") return truth(line, "plugged") ? "gamepad plugged" : "gamepad unplugged";
  if (event == "source_locked") return fmt::format("client data source locked: {}", str(line, "source"));
  if (event == "source_conflict") {
    return fmt::format("client data source conflict: {} is locked, {} sent too", str(line, "locked"),
                       str(line, "offending"));
  }
  if (event == "active_vehicle") {
    return fmt::format("active vehicle {}", line["vehicle"].IsString() ? str(line, "vehicle") : "none");
  }
  if (event == "pair_rejected") return fmt::format("pair rejected ({}): {}", str(line, "cause"), str(line, "hint"));
  if (event == "trace_format") return fmt::format("trace format version {}", num(line, "version"));
  return fmt::format("{} (unknown event)", event);
}

}  // namespace

std::string render_trace_text(std::string_view jsonl) {
  std::string out;
  std::size_t start = 0;
  while (start < jsonl.size()) {
    std::size_t end = jsonl.find('\n', start);
    if (end == std::string_view::npos) end = jsonl.size();
    const std::string_view line = jsonl.substr(start, end - start);
    start = end + 1;
    if (line.empty()) continue;
    rapidjson::Document document;
    document.Parse(line.data(), line.size());
    if (document.HasParseError() || !document.IsObject() || !document.HasMember("t_us") ||
        !document["t_us"].IsInt64()) {
      out += fmt::format("? {}\n", line);
      continue;
    }
    out += fmt::format("{:>12} {} {}\n", document["t_us"].GetInt64(), str(document, "source"),
                       describe(document));
  }
  return out;
}

}  // namespace ocp
