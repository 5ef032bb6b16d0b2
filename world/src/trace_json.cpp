// One event → one JSON line (docs/trace-format.md). Field names and value spellings here are
// the trace format: change them only with a new trace_format_version.
#include <rapidjson/stringbuffer.h>
#include <rapidjson/writer.h>

#include <string>
#include <type_traits>

#include "ocp/delivery_trace.hpp"
#include "ocp/impairments.hpp"
#include "ocp/link_recording.hpp"
#include "world/trace.hpp"

namespace ocp {
namespace {

using JsonWriter = rapidjson::Writer<rapidjson::StringBuffer>;

void key(JsonWriter& json, std::string_view name) {
  json.Key(name.data(), static_cast<rapidjson::SizeType>(name.size()));
}
void text(JsonWriter& json, std::string_view name, std::string_view value) {
  key(json, name);
  json.String(value.data(), static_cast<rapidjson::SizeType>(value.size()));
}
void number(JsonWriter& json, std::string_view name, std::uint64_t value) {
  key(json, name);
  json.Uint64(value);
}
void signed_number(JsonWriter& json, std::string_view name, std::int64_t value) {
  key(json, name);
  json.Int64(value);
}
void real(JsonWriter& json, std::string_view name, double value) {
  key(json, name);
  json.Double(value);
}
void flag(JsonWriter& json, std::string_view name, bool value) {
  key(json, name);
  json.Bool(value);
}

bool valid_utf8(std::string_view bytes) {
  rapidjson::StringStream stream(bytes.data());
  rapidjson::StringBuffer sink;
  while (static_cast<std::size_t>(stream.Tell()) < bytes.size()) {
    if (!rapidjson::UTF8<>::Validate(stream, sink)) return false;
  }
  return true;
}

// Payloads are the peer's bytes, possibly hostile: text when they are valid UTF-8 without NUL,
// otherwise hex so the trace line stays valid JSON.
void payload(JsonWriter& json, std::string_view bytes) {
  if (bytes.find('\0') == std::string_view::npos && valid_utf8(bytes)) {
    text(json, "payload", bytes);
    return;
  }
  static constexpr char digits[] = "0123456789abcdef";
  std::string hex;
  hex.reserve(bytes.size() * 2);
  for (const char byte : bytes) {
    hex += digits[static_cast<unsigned char>(byte) >> 4];
    hex += digits[static_cast<unsigned char>(byte) & 0xf];
  }
  text(json, "payload_hex", hex);
}

void write_body(JsonWriter& json, const WireFrame& frame, const TraceOptions& options) {
  text(json, "event", "frame");
  text(json, "wire", wire_name(frame.wire));
  text(json, "dir", frame_direction_name(frame.direction));
  text(json, "kind", wire_message_kind_name(frame.kind));
  number(json, "len", frame.length_prefix);
  flag(json, "drained", frame.drained);
  if (frame.ack) {
    number(json, "ack_time", frame.ack->ack_time);
    number(json, "ack_time_mac", frame.ack->ack_time_mac);
  }
  text(json, "peer", frame.peer);
  if (options.frame_payloads && !frame.drained) payload(json, frame.payload);
}

void write_body(JsonWriter& json, const FaultEvent& fault, const TraceOptions&) {
  text(json, "event", "fault");
  text(json, "side", fault_side_name(fault.side));
  text(json, "vehicle", fault.vehicle);
  text(json, "fault", fault_identifier(fault.id));
  flag(json, "active", fault.active);
}

void write_body(JsonWriter& json, const ConnectionEvent& connection, const TraceOptions&) {
  text(json, "event", "connection");
  text(json, "wire", wire_name(connection.wire));
  text(json, "change", connection_change_name(connection.change));
  text(json, "peer", connection.peer);
  if (connection.reason != nullptr) {
    text(json, "reason", error_code_id(connection.reason->code));
    text(json, "detail", connection.reason->detail);
  }
}

void write_body(JsonWriter& json, const LatencySample& sample, const TraceOptions&) {
  text(json, "event", "latency");
  key(json, "latency_ms");
  if (sample.latency_ms) json.Uint64(*sample.latency_ms); else json.Null();
  key(json, "pair_age_us");
  if (sample.pair_age) json.Int64(sample.pair_age->count()); else json.Null();
  signed_number(json, "tick_lateness_us", sample.tick_lateness.count());
  flag(json, "control_sent", sample.control_sent);
}

void write_body(JsonWriter& json, const LinkEvent& link, const TraceOptions&) {
  text(json, "event", "link");
  text(json, "route", link_route_name(link.route));
  text(json, "outcome", link_outcome_name(link.outcome));
  text(json, "kind", link_message_kind_name(link.kind));
  number(json, "id", link.message_id);
  number(json, "bytes", link.size_bytes);
  if (link.outcome == LinkOutcome::dropped) text(json, "reason", drop_reason_name(link.reason));
}

std::string_view jitter_kind_name(Impairments::JitterKind kind) {
  switch (kind) {
    case Impairments::JitterKind::none: return "none";
    case Impairments::JitterKind::uniform: return "uniform";
    case Impairments::JitterKind::normal: return "normal";
  }
  return "?";
}

void write_body(JsonWriter& json, const ImpairmentChange& change, const TraceOptions&) {
  const Impairments& set = *change.impairments;
  text(json, "event", "impairments");
  text(json, "route", link_route_name(change.route));
  signed_number(json, "delay_us", set.delay.count());
  text(json, "jitter_kind", jitter_kind_name(set.jitter_kind));
  signed_number(json, "jitter_us", set.jitter.count());
  real(json, "loss", set.loss_probability);
  flag(json, "burst_loss", set.burst_loss);
  real(json, "good_to_bad", set.good_to_bad_probability);
  real(json, "bad_to_good", set.bad_to_good_probability);
  real(json, "loss_in_good", set.loss_in_good);
  real(json, "loss_in_bad", set.loss_in_bad);
  real(json, "bandwidth_bps", set.bandwidth_bits_per_second);
  number(json, "queue_limit_bytes", set.queue_limit_bytes);
  if (set.trace) {  // only then, so traces of runs without one keep their shape
    text(json, "trace", set.trace->name());
    number(json, "queue_limit_packets", set.queue_limit_packets);
  }
  if (set.replay) text(json, "replay", set.replay->name());   // likewise
  real(json, "duplicate", set.duplicate_probability);
  real(json, "reorder", set.reorder_probability);
  signed_number(json, "reorder_extra_delay_us", set.reorder_extra_delay.count());
  flag(json, "down", set.down);
}

void write_body(JsonWriter& json, const GamepadChange& change, const TraceOptions&) {
  text(json, "event", "gamepad");
  flag(json, "plugged", change.plugged);
}

void write_body(JsonWriter& json, const SourceLocked& locked, const TraceOptions&) {
  text(json, "event", "source_locked");
  text(json, "source", client_source_name(locked.source));
}

void write_body(JsonWriter& json, const SourceConflict& conflict, const TraceOptions&) {
  text(json, "event", "source_conflict");
  text(json, "locked", client_source_name(conflict.locked));
  text(json, "offending", client_source_name(conflict.offending));
}

void write_body(JsonWriter& json, const ActiveVehicleChange& change, const TraceOptions&) {
  text(json, "event", "active_vehicle");
  key(json, "vehicle");
  if (change.vehicle) {
    json.String(change.vehicle->data(), static_cast<rapidjson::SizeType>(change.vehicle->size()));
  } else {
    json.Null();
  }
}

void write_pair(JsonWriter& json, std::string_view name, const AckPair& pair) {
  key(json, name);
  json.StartObject();
  number(json, "ack_time", pair.ack_time);
  number(json, "ack_time_mac", pair.ack_time_mac);
  json.EndObject();
}

void write_body(JsonWriter& json, const PairRejected& rejected, const TraceOptions&) {
  text(json, "event", "pair_rejected");
  write_pair(json, "rejected", rejected.rejected);
  if (rejected.judgement.nearest_issued) {
    write_pair(json, "nearest_issued", *rejected.judgement.nearest_issued);
  } else {
    key(json, "nearest_issued");
    json.Null();
  }
  text(json, "cause", pair_cause_name(rejected.judgement.cause));
  text(json, "hint", rejected.hint);
}

bool wanted(const Event& event, const TraceOptions& options) {
  if (std::holds_alternative<WireFrame>(event.body)) return options.frames;
  if (std::holds_alternative<LinkEvent>(event.body)) return options.link_messages;
  if (std::holds_alternative<LatencySample>(event.body)) return options.latency_samples;
  return true;
}

}  // namespace

void append_trace_line(const Event& event, const TraceOptions& options, std::string& out) {
  if (!wanted(event, options)) return;
  rapidjson::StringBuffer buffer;
  JsonWriter json(buffer);
  json.StartObject();
  signed_number(json, "t_us", event.time.count());
  // "streamer:truck-1"; a component named like its kind (the default Player) is just "player".
  std::string source(component_kind_name(event.component.kind));
  if (!event.component.name.empty() && event.component.name != source) {
    source += ':';
    source += event.component.name;
  }
  text(json, "source", source);
  std::visit([&](const auto& body) { write_body(json, body, options); }, event.body);
  json.EndObject();
  out.append(buffer.GetString(), buffer.GetSize());
  out += '\n';
}

std::string trace_header_line() {
  return "{\"t_us\":0,\"source\":\"trace\",\"event\":\"trace_format\",\"version\":" +
         std::to_string(trace_format_version) + "}\n";
}

}  // namespace ocp
