// OcpControlMessage (SPEC §3.2): Streamer → vehicle, every 10 ms.
#include "json_codec_reader.hpp"
#include "json_codec_writer.hpp"
#include "ocp/json_codec.hpp"

namespace ocp {
namespace {

using json_detail::Decoder;
using json_detail::FieldSet;
using json_detail::FieldTable;

enum class TelemetryField : std::uint8_t { latency, fault, fault_reason, missing_cameras, unknown };
constexpr FieldTable<TelemetryField> telemetry_fields({
    {TelemetryField::latency, "latency"},
    {TelemetryField::fault, "fault"},
    {TelemetryField::fault_reason, "fault_reason"},
    {TelemetryField::missing_cameras, "missing_cameras"},
});
// missing_cameras is optional.
constexpr std::array required_telemetry_fields{TelemetryField::latency, TelemetryField::fault,
                                               TelemetryField::fault_reason};

enum class ControlField : std::uint8_t {
  controller,
  telemetry,
  ack_time,
  ack_time_mac,
  client_user_data,
  unknown
};
constexpr FieldTable<ControlField> control_fields({
    {ControlField::controller, "controller"},
    {ControlField::telemetry, "telemetry"},
    {ControlField::ack_time, "ack_time"},
    {ControlField::ack_time_mac, "ack_time_mac"},
    {ControlField::client_user_data, "client_user_data"},
});
// controller and client_user_data are optional.
constexpr std::array required_control_fields{ControlField::telemetry, ControlField::ack_time,
                                             ControlField::ack_time_mac};

bool read_telemetry(Decoder& decoder, std::size_t index, Telemetry& out) {
  FieldSet<TelemetryField> seen;
  std::size_t hint = 0;
  out.missing_cameras.clear();
  const bool ok = decoder.for_each_member(index, [&](std::string_view key, std::size_t value) {
    const TelemetryField field = telemetry_fields.find(key, hint);
    seen.mark(field);
    switch (field) {
      case TelemetryField::latency: return decoder.read_integral(value, out.latency_ms);
      case TelemetryField::fault: return decoder.read_bool(value, out.fault);
      case TelemetryField::fault_reason: return decoder.read_string(value, out.fault_reason);
      case TelemetryField::missing_cameras:
        return decoder.read_string_array(value, out.missing_cameras);
      case TelemetryField::unknown: break;
    }
    return true;  // unknown fields are ignored
  });
  return ok &&
         json_detail::require_fields<required_telemetry_fields>(decoder, telemetry_fields, seen);
}

bool read_control_message(Decoder& decoder, std::size_t index, OcpControlMessage& out) {
  FieldSet<ControlField> seen;
  std::size_t hint = 0;
  const bool ok = decoder.for_each_member(index, [&](std::string_view key, std::size_t value) {
    const ControlField field = control_fields.find(key, hint);
    seen.mark(field);
    switch (field) {
      case ControlField::controller:
        return json_detail::read_optional_controller(decoder, value, out.controller);
      case ControlField::telemetry: return read_telemetry(decoder, value, out.telemetry);
      case ControlField::ack_time: return decoder.read_u64(value, out.ack.ack_time);
      case ControlField::ack_time_mac: return decoder.read_u32(value, out.ack.ack_time_mac);
      case ControlField::client_user_data:
        if (decoder.is_null(value)) {
          out.client_user_data.reset();
          return true;
        }
        return decoder.read_raw(value, out.client_user_data.emplace());
      case ControlField::unknown: break;
    }
    return true;  // unknown fields are ignored
  });
  return ok && json_detail::require_fields<required_control_fields>(decoder, control_fields, seen);
}

}  // namespace

Result<OcpControlMessage> decode_control_message(std::string_view json) {
  return json_detail::decode_document<OcpControlMessage>(json, read_control_message);
}

struct ControlMessageDecoder::State {
  json_detail::Tape tape;
  Status tokenized = Ok{};
};

ControlMessageDecoder::ControlMessageDecoder() : state_(std::make_unique<State>()) {}
ControlMessageDecoder::~ControlMessageDecoder() = default;

std::optional<AckPair> ControlMessageDecoder::start(std::string_view json) {
  json_detail::Tape& tape = state_->tape;
  if (tape.text.capacity() > (std::size_t{1} << 20)) tape = json_detail::Tape{};   // a hostile megabyte is not kept
  state_->tokenized = json_detail::tokenize(json, tape);
  if (!state_->tokenized) return std::nullopt;
  // The last occurrence of each key, read by the same readers read_control_message uses.
  std::size_t ack_time = 0;
  std::size_t ack_time_mac = 0;
  const std::size_t end = tape.tokens[0].end_index;
  for (std::size_t key = 1; key < end; key = tape.next(key + 1)) {
    const std::string_view name = tape.text_of(tape.tokens[key]);
    if (name == "ack_time") ack_time = key + 1;
    if (name == "ack_time_mac") ack_time_mac = key + 1;
  }
  json_detail::Decoder decoder(tape);
  AckPair pair;
  if (ack_time == 0 || ack_time_mac == 0 || !decoder.read_u64(ack_time, pair.ack_time) ||
      !decoder.read_u32(ack_time_mac, pair.ack_time_mac)) {
    return std::nullopt;
  }
  return pair;
}

Result<OcpControlMessage> ControlMessageDecoder::finish() {
  if (!state_->tokenized) return state_->tokenized.error();
  return json_detail::decode_tape<OcpControlMessage>(state_->tape, read_control_message);
}

void encode_control_message(const OcpControlMessage& message, std::string& out) {
  json_detail::JsonWriter writer(out);
  writer.literal("{\"controller\":");
  writer.optional_controller(message.controller);
  writer.literal(",\"telemetry\":{\"latency\":");
  writer.u64(message.telemetry.latency_ms);
  writer.literal(",\"fault\":");
  writer.boolean(message.telemetry.fault);
  writer.literal(",\"fault_reason\":");
  writer.string(message.telemetry.fault_reason);
  writer.literal(",\"missing_cameras\":");
  writer.string_array(message.telemetry.missing_cameras);
  writer.literal("},");
  writer.ack_pair_members(message.ack);
  if (message.client_user_data) {
    writer.literal(",\"client_user_data\":");
    writer.raw(*message.client_user_data);
  }
  writer.literal('}');
}

void encode_controller(const Controller& controller, std::string& out) {
  json_detail::JsonWriter writer(out);
  writer.controller(controller);
}

}  // namespace ocp
