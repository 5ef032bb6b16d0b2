// VehicleResponseMessage (SPEC §3.3): vehicle → Streamer, continuously.
#include "json_codec_reader.hpp"
#include "json_codec_writer.hpp"
#include "ocp/json_codec.hpp"

namespace ocp {
namespace {

using json_detail::Decoder;
using json_detail::FieldTable;

constexpr FieldTable<3> response_fields({"ack_time", "ack_time_mac", "vehicle_user_data"});

bool read_response(Decoder& decoder, std::size_t index, VehicleResponseMessage& out) {
  unsigned seen = 0;
  std::size_t hint = 0;
  const bool ok = decoder.for_each_member(index, [&](std::string_view key, std::size_t value) {
    const std::size_t field = response_fields.find(key, hint);
    seen |= 1U << field;
    switch (field) {
      case 0: return decoder.read_u64(value, out.ack.ack_time);
      case 1: return decoder.read_u32(value, out.ack.ack_time_mac);
      case 2:
        if (decoder.is_null(value)) {
          out.vehicle_user_data.reset();
          return true;
        }
        return json_detail::read_vehicle_user_data(decoder, value, out.vehicle_user_data.emplace());
      default: return true;
    }
  });
  if (!ok) return false;
  if ((seen & 1U) == 0) return decoder.fail_missing("ack_time");
  if ((seen & 2U) == 0) return decoder.fail_missing("ack_time_mac");
  return true;
}

}  // namespace

Result<VehicleResponseMessage> decode_vehicle_response(std::string_view json) {
  return json_detail::decode_document<VehicleResponseMessage>(json, read_response);
}

void encode_vehicle_response(const VehicleResponseMessage& message, std::string& out) {
  json_detail::JsonWriter writer(out);
  writer.literal("{\"ack_time\":");
  writer.u64(message.ack.ack_time);
  writer.literal(",\"ack_time_mac\":");
  writer.u64(message.ack.ack_time_mac);
  if (message.vehicle_user_data) {
    writer.literal(",\"vehicle_user_data\":");
    writer.vehicle_user_data(*message.vehicle_user_data);
  }
  writer.literal('}');
}

}  // namespace ocp
