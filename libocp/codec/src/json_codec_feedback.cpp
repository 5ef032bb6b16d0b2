// VehicleOcpShared (SPEC §4.1): Player → operator client, once per Player frame.
// Fields typed Option<…> in seed 004 may be null or absent; is_monitor (our addition, absent
// from the seed) defaults to false when absent.
#include "json_codec_reader.hpp"
#include "json_codec_writer.hpp"
#include "ocp/json_codec.hpp"

namespace ocp {
namespace {

using json_detail::Decoder;
using json_detail::FieldSet;
using json_detail::FieldTable;

enum class FeedbackField : std::uint8_t {
  ping_latency_ms,
  message_latency_roundtrip,
  ms_since_last_vehicle_data,
  missing_cameras,
  sender_fault,
  receiver_fault,
  vehicle_data,
  last_remote_input,
  ack_time,
  ack_time_mac,
  is_monitor,
  unknown
};
constexpr FieldTable<FeedbackField> feedback_fields({
    {FeedbackField::ping_latency_ms, "ping_latency_ms"},
    {FeedbackField::message_latency_roundtrip, "message_latency_roundtrip"},
    {FeedbackField::ms_since_last_vehicle_data, "ms_since_last_vehicle_data"},
    {FeedbackField::missing_cameras, "missing_cameras"},
    {FeedbackField::sender_fault, "sender_fault"},
    {FeedbackField::receiver_fault, "receiver_fault"},
    {FeedbackField::vehicle_data, "vehicle_data"},
    {FeedbackField::last_remote_input, "last_remote_input"},
    {FeedbackField::ack_time, "ack_time"},
    {FeedbackField::ack_time_mac, "ack_time_mac"},
    {FeedbackField::is_monitor, "is_monitor"},
});
// The Option<…> fields and is_monitor may be absent.
constexpr std::array required_feedback_fields{
    FeedbackField::ping_latency_ms, FeedbackField::ms_since_last_vehicle_data,
    FeedbackField::sender_fault,    FeedbackField::receiver_fault,
    FeedbackField::ack_time,        FeedbackField::ack_time_mac};

enum class SharedField : std::uint8_t { vehicle_feedback, last_input, unknown };
constexpr FieldTable<SharedField> shared_fields({
    {SharedField::vehicle_feedback, "vehicle_feedback"},
    {SharedField::last_input, "last_input"},
});
// last_input is an Option<…>.
constexpr std::array required_shared_fields{SharedField::vehicle_feedback};

bool read_feedback(Decoder& decoder, std::size_t index, VehicleFeedback& out) {
  FieldSet<FeedbackField> seen;
  std::size_t hint = 0;
  const bool ok = decoder.for_each_member(index, [&](std::string_view key, std::size_t value) {
    const FeedbackField field = feedback_fields.find(key, hint);
    seen.mark(field);
    const bool null = decoder.is_null(value);
    switch (field) {
      case FeedbackField::ping_latency_ms: return decoder.read_u64(value, out.ping_latency_ms);
      case FeedbackField::message_latency_roundtrip:
        if (null) {
          out.message_latency_roundtrip.reset();
          return true;
        }
        return decoder.read_u64(value, out.message_latency_roundtrip.emplace());
      case FeedbackField::ms_since_last_vehicle_data:
        return decoder.read_u64(value, out.ms_since_last_vehicle_data);
      case FeedbackField::missing_cameras:
        if (null) {
          out.missing_cameras.reset();
          return true;
        }
        return decoder.read_string_array(value, out.missing_cameras.emplace());
      case FeedbackField::sender_fault: return decoder.read_string_array(value, out.sender_fault);
      case FeedbackField::receiver_fault:
        return decoder.read_string_array(value, out.receiver_fault);
      case FeedbackField::vehicle_data:
        if (null) {
          out.vehicle_data.reset();
          return true;
        }
        return json_detail::read_vehicle_user_data(decoder, value, out.vehicle_data.emplace());
      case FeedbackField::last_remote_input:
        return json_detail::read_optional_controller(decoder, value, out.last_remote_input);
      case FeedbackField::ack_time: return decoder.read_u64(value, out.ack.ack_time);
      case FeedbackField::ack_time_mac: return decoder.read_u32(value, out.ack.ack_time_mac);
      case FeedbackField::is_monitor: return decoder.read_bool(value, out.is_monitor);
      case FeedbackField::unknown: break;
    }
    return true;  // unknown fields are ignored
  });
  return ok &&
         json_detail::require_fields<required_feedback_fields>(decoder, feedback_fields, seen);
}

bool read_shared(Decoder& decoder, std::size_t index, VehicleOcpShared& out) {
  FieldSet<SharedField> seen;
  std::size_t hint = 0;
  const bool ok = decoder.for_each_member(index, [&](std::string_view key, std::size_t value) {
    const SharedField field = shared_fields.find(key, hint);
    seen.mark(field);
    switch (field) {
      case SharedField::vehicle_feedback:
        out.vehicle_feedback.clear();
        return decoder.for_each_member(value, [&](std::string_view name, std::size_t entry) {
          VehicleFeedback& feedback = out.vehicle_feedback[std::string(name)];
          feedback = VehicleFeedback{};  // a repeated name: the last one wins
          return read_feedback(decoder, entry, feedback);
        });
      case SharedField::last_input:
        return json_detail::read_optional_controller(decoder, value, out.last_input);
      case SharedField::unknown: break;
    }
    return true;  // unknown fields are ignored
  });
  return ok && json_detail::require_fields<required_shared_fields>(decoder, shared_fields, seen);
}

void write_optional_string_array(json_detail::JsonWriter& writer,
                                 const std::optional<std::vector<std::string>>& values) {
  if (values) {
    writer.string_array(*values);
  } else {
    writer.null();
  }
}

void write_feedback(json_detail::JsonWriter& writer, const VehicleFeedback& feedback) {
  writer.literal("{\"ping_latency_ms\":");
  writer.u64(feedback.ping_latency_ms);
  writer.literal(",\"message_latency_roundtrip\":");
  if (feedback.message_latency_roundtrip) {
    writer.u64(*feedback.message_latency_roundtrip);
  } else {
    writer.null();
  }
  writer.literal(",\"ms_since_last_vehicle_data\":");
  writer.u64(feedback.ms_since_last_vehicle_data);
  writer.literal(",\"missing_cameras\":");
  write_optional_string_array(writer, feedback.missing_cameras);
  writer.literal(",\"sender_fault\":");
  writer.string_array(feedback.sender_fault);
  writer.literal(",\"receiver_fault\":");
  writer.string_array(feedback.receiver_fault);
  writer.literal(",\"vehicle_data\":");
  if (feedback.vehicle_data) {
    writer.vehicle_user_data(*feedback.vehicle_data);
  } else {
    writer.null();
  }
  writer.literal(",\"last_remote_input\":");
  writer.optional_controller(feedback.last_remote_input);
  writer.literal(",\"ack_time\":");
  writer.u64(feedback.ack.ack_time);
  writer.literal(",\"ack_time_mac\":");
  writer.u64(feedback.ack.ack_time_mac);
  writer.literal(",\"is_monitor\":");
  writer.boolean(feedback.is_monitor);
  writer.literal('}');
}

}  // namespace

Result<VehicleOcpShared> decode_vehicle_ocp_shared(std::string_view json) {
  return json_detail::decode_document<VehicleOcpShared>(json, read_shared);
}

void encode_vehicle_ocp_shared(const VehicleOcpShared& message, std::string& out) {
  json_detail::JsonWriter writer(out);
  writer.literal("{\"vehicle_feedback\":{");
  bool first = true;
  for (const auto& [name, feedback] : message.vehicle_feedback) {
    if (!first) writer.literal(',');
    first = false;
    writer.string(name);
    writer.literal(':');
    write_feedback(writer, feedback);
  }
  writer.literal("},\"last_input\":");
  writer.optional_controller(message.last_input);
  writer.literal('}');
}

}  // namespace ocp
