// extract-link (extract_link.hpp): reads the trace line by line, pairs each link message's
// `sent` with its `delivered` or `dropped` by (route, id), and writes one recorded outcome per
// message in send order.
#include "scenario/extract_link.hpp"

#include <rapidjson/document.h>

#include <algorithm>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>
#include <unordered_map>
#include <vector>

#include "ocp/bounded_file.hpp"
#include "ocp/exit_codes.hpp"
#include "world/trace.hpp"

namespace ocp::scenario {
namespace {

// One message of one route while the trace is read.
struct ExtractedMessage {
  std::int64_t sent_us = 0;
  std::int64_t delay_us = 0;
  bool lost = false;
  bool settled = false;   // delivered or dropped seen
};

struct ExtractedRoute {
  std::vector<ExtractedMessage> messages;
  std::unordered_map<std::uint64_t, std::size_t> by_id;
  bool any_settled = false;
};

struct LatencyPoint {
  std::int64_t t_us = 0;
  std::int64_t latency_ms = 0;
};

std::string_view json_text(const rapidjson::Value& object, const char* key) {
  const auto it = object.FindMember(key);
  if (it == object.MemberEnd() || !it->value.IsString()) return {};
  return {it->value.GetString(), it->value.GetStringLength()};
}

class LinkExtractor {
 public:
  LinkExtractor(std::string name, std::string vehicle) : name_(std::move(name)), vehicle_(std::move(vehicle)) {}

  void line(std::size_t number, std::string_view text) {
    if (text.find_first_not_of(" \t\r") == std::string_view::npos) return;
    rapidjson::Document doc;
    doc.Parse(text.data(), text.size());
    if (doc.HasParseError() || !doc.IsObject()) fail(number, "not a JSON object (is this a trace.jsonl?)");
    const auto t_us = doc.FindMember("t_us");
    const std::string_view source = json_text(doc, "source"), event = json_text(doc, "event");
    if (t_us == doc.MemberEnd() || !t_us->value.IsInt64() || source.empty() || event.empty()) {
      fail(number, "a trace line needs t_us (integer), source and event (docs/trace-format.md)");
    }
    if (number == 1) return header(number, doc, event);
    note_vehicle(source);
    const std::int64_t t = t_us->value.GetInt64();
    if (event == "link" && source == "link:" + vehicle_) link(number, doc, t);
    if (event == "latency" && source == "streamer:" + vehicle_) latency(doc, t);
  }

  const std::set<std::string>& vehicles() const { return vehicles_; }
  std::size_t index_of(LinkRoute route) const { return route == LinkRoute::to_streamer ? 0 : 1; }
  const ExtractedRoute& route(LinkRoute route) const { return routes_[index_of(route)]; }
  const std::vector<LatencyPoint>& latencies() const { return latencies_; }
  [[noreturn]] void fail(std::size_t number, const std::string& reason) const {
    throw ExtractLinkError(name_ + ":" + std::to_string(number) + ": " + reason);
  }

 private:
  void header(std::size_t number, const rapidjson::Document& doc, std::string_view event) {
    const auto version = doc.FindMember("version");
    if (event != "trace_format" || version == doc.MemberEnd() || !version->value.IsInt()) {
      fail(number, "the first line is not the trace_format header (is this a trace.jsonl?)");
    }
    if (version->value.GetInt() != trace_format_version) {
      fail(number, "trace format version " + std::to_string(version->value.GetInt()) + " (this build reads " +
                       std::to_string(trace_format_version) + ")");
    }
  }

  void note_vehicle(std::string_view source) {
    for (const std::string_view prefix : {std::string_view("link:"), std::string_view("streamer:")}) {
      if (source.substr(0, prefix.size()) == prefix) vehicles_.emplace(source.substr(prefix.size()));
    }
  }

  void link(std::size_t number, const rapidjson::Document& doc, std::int64_t t) {
    const std::string_view route_name = json_text(doc, "route"), outcome = json_text(doc, "outcome");
    const auto id = doc.FindMember("id");
    if (id == doc.MemberEnd() || !id->value.IsUint64() || (route_name != "to_streamer" && route_name != "to_player")) {
      fail(number, "a link event needs route (to_streamer or to_player) and id");
    }
    ExtractedRoute& route = routes_[route_name == "to_streamer" ? 0 : 1];
    if (outcome == "sent") {
      if (!route.by_id.emplace(id->value.GetUint64(), route.messages.size()).second) fail(number, "message id sent twice");
      route.messages.push_back(ExtractedMessage{t, 0, false, false});
      return;
    }
    const auto found = route.by_id.find(id->value.GetUint64());
    if (found == route.by_id.end()) return;          // sent before the trace began
    ExtractedMessage& message = route.messages[found->second];
    if (message.settled) return;                     // a duplicate: the first delivery counts
    if (outcome != "delivered" && outcome != "dropped") fail(number, "unknown link outcome '" + escaped_excerpt(outcome) + "'");
    message.settled = route.any_settled = true;
    message.lost = outcome == "dropped";
    message.delay_us = t - message.sent_us;
  }

  void latency(const rapidjson::Document& doc, std::int64_t t) {
    const auto value = doc.FindMember("latency_ms");
    if (value != doc.MemberEnd() && value->value.IsInt64()) latencies_.push_back({t, value->value.GetInt64()});
  }

  std::string name_, vehicle_;
  std::set<std::string> vehicles_;
  ExtractedRoute routes_[2];
  std::vector<LatencyPoint> latencies_;
};

std::string known_vehicle_names(const std::set<std::string>& names) {
  std::string list;
  for (const std::string& name : names) list += (list.empty() ? "" : ", ") + name;
  return list.empty() ? "none: the trace has no link or streamer events" : list;
}

// Every line through the extractor; the vehicle named (or the only one) must be in the trace.
LinkExtractor read_trace(std::string_view jsonl, const ExtractLinkOptions& options, std::string vehicle) {
  LinkExtractor extractor(options.trace_path, vehicle);
  std::size_t number = 0;
  while (!jsonl.empty()) {
    const auto end = jsonl.find('\n');
    extractor.line(++number, jsonl.substr(0, end));
    jsonl = end == std::string_view::npos ? std::string_view{} : jsonl.substr(end + 1);
  }
  if (number == 0) throw ExtractLinkError(options.trace_path + ": empty trace");
  return extractor;
}

// The Streamer's loop latency at `t` (the last sample at or before it, else the first).
std::int64_t rtt_at(const std::vector<LatencyPoint>& latencies, std::int64_t t) {
  const auto after = std::upper_bound(latencies.begin(), latencies.end(), t,
                                      [](std::int64_t time, const LatencyPoint& point) { return time < point.t_us; });
  return (after == latencies.begin() ? *after : *(after - 1)).latency_ms;
}



// One route's messages as recorded outcomes; returns the header comment about it.
std::string record_route(const LinkExtractor& extractor, LinkRoute route_id, bool rtt_half, LinkRecording& out) {
  const ExtractedRoute& route = extractor.route(route_id);
  const std::string name(link_route_name(route_id));
  // A route whose messages were all sent but none settled was seen from one end only.
  const bool halved = rtt_half || (!route.messages.empty() && !route.any_settled);
  out.set_clock(route_id, halved ? LinkRecording::Clock::rtt_half : LinkRecording::Clock::measured);
  if (halved && !route.messages.empty() && extractor.latencies().empty()) {
    throw ExtractLinkError(name + ": the clocks differ (delays are RTT/2), but the trace has no latency samples "
                                  "of this vehicle to take the RTT from");
  }
  std::vector<RecordedMessage>& recorded = out.route(route_id);
  std::size_t lost = 0, unsettled = 0;
  for (const ExtractedMessage& message : route.messages) {
    if (!halved && !message.settled) {
      unsettled = route.messages.size() - recorded.size();   // in flight when the trace ends
      break;
    }
    const std::int64_t delay = halved ? rtt_at(extractor.latencies(), message.sent_us) * 1000 / 2 : message.delay_us;
    recorded.push_back(RecordedMessage{Micros{message.sent_us}, Micros{delay}, message.lost});
    lost += message.lost ? 1 : 0;
  }
  std::string comment = name + ": " + std::to_string(recorded.size()) + " messages, " + std::to_string(lost) + " lost; ";
  comment += halved ? "delay = RTT/2 (the two ends' clocks differ: the Streamer's latency samples, halved)"
                    : "delay = delivered - sent, on one clock";
  if (unsettled > 0) comment += "; " + std::to_string(unsettled) + " still in flight when the trace ended, left out";
  if (route.messages.empty()) comment += " (no messages of this route in the trace)";
  return comment;
}

}  // namespace

ExtractedLink extract_link(std::string_view trace_jsonl, const ExtractLinkOptions& options) {
  std::string vehicle = options.vehicle;
  if (vehicle.empty()) {
    const LinkExtractor first = read_trace(trace_jsonl, options, "");
    if (first.vehicles().size() != 1) {
      throw ExtractLinkError("name the vehicle with --vehicle NAME; the trace has: " + known_vehicle_names(first.vehicles()));
    }
    vehicle = *first.vehicles().begin();
  }
  const LinkExtractor extractor = read_trace(trace_jsonl, options, vehicle);
  if (!extractor.vehicles().contains(vehicle)) {
    throw ExtractLinkError("unknown vehicle '" + vehicle + "'; the trace has: " + known_vehicle_names(extractor.vehicles()));
  }
  ExtractedLink extracted;
  extracted.recording.set_name(options.trace_path);
  extracted.comments.push_back("link recording of vehicle " + vehicle + ", extracted from " + options.trace_path +
                               " by ocp_scenario extract-link (docs/link-recording.md)");
  extracted.comments.push_back("to_player is the vehicle's uplink (video, feedback), to_streamer its downlink (control)");
  for (const LinkRoute route : {LinkRoute::to_streamer, LinkRoute::to_player}) {
    extracted.comments.push_back(record_route(extractor, route, options.rtt_half, extracted.recording));
  }
  if (extracted.recording.route(LinkRoute::to_streamer).empty() && extracted.recording.route(LinkRoute::to_player).empty()) {
    throw ExtractLinkError(options.trace_path + ": vehicle " + vehicle + " has no settled link messages to record");
  }
  return extracted;
}

int extract_link_command(const ExtractLinkOptions& options, std::ostream& out, std::ostream& err) {
  const auto text = read_bounded_file(options.trace_path, file_kinds::trace_jsonl);
  if (!text) {
    err << "error: " << text.error().detail << "\n";
    return cli::exit_usage_error;
  }
  try {
    const ExtractedLink extracted = extract_link(*text, options);
    out << extracted.recording.format(extracted.comments);
    return cli::exit_ok;
  } catch (const ExtractLinkError& error) {
    err << "error: " << error.what() << "\n";
    return cli::exit_usage_error;
  }
}

}  // namespace ocp::scenario
