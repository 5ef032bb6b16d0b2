// VehicleResponseMessage (SPEC §3.3): vehicle → Streamer, continuously.
#include "json_codec_reader.hpp"
#include "json_codec_writer.hpp"
#include "ocp/json_codec.hpp"

namespace ocp {
namespace {

using json_detail::Decoder;
using json_detail::FieldSet;
using json_detail::FieldTable;

enum class ResponseField : std::uint8_t { ack_time, ack_time_mac, vehicle_user_data, unknown };
constexpr FieldTable<ResponseField> response_fields({
    {ResponseField::ack_time, "ack_time"},
    {ResponseField::ack_time_mac, "ack_time_mac"},
    {ResponseField::vehicle_user_data, "vehicle_user_data"},
});
constexpr std::array required_response_fields{ResponseField::ack_time,
                                              ResponseField::ack_time_mac};

bool read_response(Decoder& decoder, std::size_t index, VehicleResponseMessage& out) {
  FieldSet<ResponseField> seen;
  std::size_t hint = 0;
  const bool ok = decoder.for_each_member(index, [&](std::string_view key, std::size_t value) {
    const ResponseField field = response_fields.find(key, hint);
    seen.mark(field);
    switch (field) {
      case ResponseField::ack_time: return decoder.read_u64(value, out.ack.ack_time);
      case ResponseField::ack_time_mac: return decoder.read_u32(value, out.ack.ack_time_mac);
      case ResponseField::vehicle_user_data:
        if (decoder.is_null(value)) {
          out.vehicle_user_data.reset();
          return true;
        }
        return json_detail::read_vehicle_user_data(decoder, value, out.vehicle_user_data.emplace());
      case ResponseField::unknown: break;
    }
    return true;  // unknown fields are ignored
  });
  return ok &&
         json_detail::require_fields<required_response_fields>(decoder, response_fields, seen);
}

}  // namespace

Result<VehicleResponseMessage> decode_vehicle_response(std::string_view json) {
  return json_detail::decode_document<VehicleResponseMessage>(json, read_response);
}

void encode_vehicle_response(const VehicleResponseMessage& message, std::string& out) {
  json_detail::JsonWriter writer(out);
  writer.literal('{');
  writer.ack_pair_members(message.ack);
  if (message.vehicle_user_data) {
    writer.literal(",\"vehicle_user_data\":");
    writer.vehicle_user_data(*message.vehicle_user_data);
  }
  writer.literal('}');
}

}  // namespace ocp
