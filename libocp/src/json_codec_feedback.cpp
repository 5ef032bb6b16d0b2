// VehicleOcpShared (SPEC §4.1): Player → operator client, once per Player frame.
// Fields typed Option<…> in seed 004 may be null or absent; is_monitor (our addition, absent
// from the seed) defaults to false when absent.
#include "json_codec_reader.hpp"
#include "json_codec_writer.hpp"
#include "ocp/json_codec.hpp"

namespace ocp {
namespace {

using json_detail::Decoder;
using json_detail::FieldTable;

constexpr FieldTable<11> feedback_fields(
    {"ping_latency_ms", "message_latency_roundtrip", "ms_since_last_vehicle_data",
     "missing_cameras", "sender_fault", "receiver_fault", "vehicle_data", "last_remote_input",
     "ack_time", "ack_time_mac", "is_monitor"});
constexpr unsigned required_feedback_fields =
    (1U << 0) | (1U << 2) | (1U << 4) | (1U << 5) | (1U << 8) | (1U << 9);
constexpr FieldTable<2> shared_fields({"vehicle_feedback", "last_input"});

bool read_feedback(Decoder& decoder, std::size_t index, VehicleFeedback& out) {
  unsigned seen = 0;
  std::size_t hint = 0;
  const bool ok = decoder.for_each_member(index, [&](std::string_view key, std::size_t value) {
    const std::size_t field = feedback_fields.find(key, hint);
    seen |= 1U << field;
    const bool null = decoder.is_null(value);
    switch (field) {
      case 0: return decoder.read_u64(value, out.ping_latency_ms);
      case 1:
        if (null) {
          out.message_latency_roundtrip.reset();
          return true;
        }
        return decoder.read_u64(value, out.message_latency_roundtrip.emplace());
      case 2: return decoder.read_u64(value, out.ms_since_last_vehicle_data);
      case 3:
        if (null) {
          out.missing_cameras.reset();
          return true;
        }
        return decoder.read_string_array(value, out.missing_cameras.emplace());
      case 4: return decoder.read_string_array(value, out.sender_fault);
      case 5: return decoder.read_string_array(value, out.receiver_fault);
      case 6:
        if (null) {
          out.vehicle_data.reset();
          return true;
        }
        return json_detail::read_vehicle_user_data(decoder, value, out.vehicle_data.emplace());
      case 7: return json_detail::read_optional_controller(decoder, value, out.last_remote_input);
      case 8: return decoder.read_u64(value, out.ack.ack_time);
      case 9: return decoder.read_u32(value, out.ack.ack_time_mac);
      case 10: return decoder.read_bool(value, out.is_monitor);
      default: return true;
    }
  });
  if (!ok) return false;
  for (std::size_t i = 0; i < 11; ++i) {
    const unsigned bit = 1U << i;
    if ((required_feedback_fields & bit) != 0 && (seen & bit) == 0) {
      return decoder.fail_missing(feedback_fields.name(i));
    }
  }
  return true;
}

bool read_shared(Decoder& decoder, std::size_t index, VehicleOcpShared& out) {
  bool seen_feedback = false;
  std::size_t hint = 0;
  const bool ok = decoder.for_each_member(index, [&](std::string_view key, std::size_t value) {
    switch (shared_fields.find(key, hint)) {
      case 0:
        seen_feedback = true;
        out.vehicle_feedback.clear();
        return decoder.for_each_member(value, [&](std::string_view name, std::size_t entry) {
          VehicleFeedback& feedback = out.vehicle_feedback[std::string(name)];
          feedback = VehicleFeedback{};  // a repeated name: the last one wins
          return read_feedback(decoder, entry, feedback);
        });
      case 1: return json_detail::read_optional_controller(decoder, value, out.last_input);
      default: return true;
    }
  });
  if (!ok) return false;
  if (!seen_feedback) return decoder.fail_missing("vehicle_feedback");
  return true;
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
