// OcpControlMessage (SPEC §3.2): Streamer → vehicle, every 10 ms.
#include "json_codec_reader.hpp"
#include "json_codec_writer.hpp"
#include "ocp/json_codec.hpp"

namespace ocp {
namespace {

using json_detail::Decoder;
using json_detail::FieldTable;

constexpr FieldTable<4> telemetry_fields({"latency", "fault", "fault_reason", "missing_cameras"});
constexpr FieldTable<5> control_fields(
    {"controller", "telemetry", "ack_time", "ack_time_mac", "client_user_data"});

bool read_telemetry(Decoder& decoder, std::size_t index, Telemetry& out) {
  unsigned seen = 0;
  std::size_t hint = 0;
  out.missing_cameras.clear();
  const bool ok = decoder.for_each_member(index, [&](std::string_view key, std::size_t value) {
    const std::size_t field = telemetry_fields.find(key, hint);
    seen |= 1U << field;
    switch (field) {
      case 0: return decoder.read_integral(value, out.latency_ms);
      case 1: return decoder.read_bool(value, out.fault);
      case 2: return decoder.read_string(value, out.fault_reason);
      case 3: return decoder.read_string_array(value, out.missing_cameras);
      default: return true;
    }
  });
  if (!ok) return false;
  for (std::size_t i = 0; i < 3; ++i) {  // missing_cameras is optional
    if ((seen & (1U << i)) == 0) return decoder.fail_missing(telemetry_fields.name(i));
  }
  return true;
}

bool read_control_message(Decoder& decoder, std::size_t index, OcpControlMessage& out) {
  unsigned seen = 0;
  std::size_t hint = 0;
  const bool ok = decoder.for_each_member(index, [&](std::string_view key, std::size_t value) {
    const std::size_t field = control_fields.find(key, hint);
    seen |= 1U << field;
    switch (field) {
      case 0: return json_detail::read_optional_controller(decoder, value, out.controller);
      case 1: return read_telemetry(decoder, value, out.telemetry);
      case 2: return decoder.read_u64(value, out.ack.ack_time);
      case 3: return decoder.read_u32(value, out.ack.ack_time_mac);
      case 4:
        if (decoder.is_null(value)) {
          out.client_user_data.reset();
          return true;
        }
        return decoder.read_raw(value, out.client_user_data.emplace());
      default: return true;
    }
  });
  if (!ok) return false;
  for (std::size_t i = 1; i < 4; ++i) {  // controller and client_user_data are optional
    if ((seen & (1U << i)) == 0) return decoder.fail_missing(control_fields.name(i));
  }
  return true;
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
  writer.literal("},\"ack_time\":");
  writer.u64(message.ack.ack_time);
  writer.literal(",\"ack_time_mac\":");
  writer.u64(message.ack.ack_time_mac);
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
