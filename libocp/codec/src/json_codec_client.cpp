// ClientOcpShared (SPEC §4.2): operator client → Player. Every field is optional; null counts
// as absent.
#include "json_codec_reader.hpp"
#include "json_codec_writer.hpp"
#include "ocp/json_codec.hpp"

namespace ocp {
namespace {

using json_detail::Decoder;
using json_detail::FieldTable;

// Every field of the client's messages is optional, so these readers keep no FieldSet.
enum class EntryField : std::uint8_t {
  user_data,
  ocp_disable_gamepad,
  ack_time_returned,
  ack_time_mac_returned,
  unknown
};
constexpr FieldTable<EntryField> entry_fields({
    {EntryField::user_data, "user_data"},
    {EntryField::ocp_disable_gamepad, "ocp_disable_gamepad"},
    {EntryField::ack_time_returned, "ack_time_returned"},
    {EntryField::ack_time_mac_returned, "ack_time_mac_returned"},
});

enum class ClientField : std::uint8_t { active_vehicle, client_user_data, unknown };
constexpr FieldTable<ClientField> client_fields({
    {ClientField::active_vehicle, "active_vehicle"},
    {ClientField::client_user_data, "client_user_data"},
});

bool read_entry(Decoder& decoder, std::size_t index, ClientVehicleEntry& out) {
  std::size_t hint = 0;
  return decoder.for_each_member(index, [&](std::string_view key, std::size_t value) {
    const EntryField field = entry_fields.find(key, hint);
    const bool null = decoder.is_null(value);
    switch (field) {
      case EntryField::user_data:
        if (null) {
          out.user_data.reset();
          return true;
        }
        return decoder.read_raw(value, out.user_data.emplace());
      case EntryField::ocp_disable_gamepad:
        if (null) {
          out.ocp_disable_gamepad.reset();
          return true;
        }
        return decoder.read_bool(value, out.ocp_disable_gamepad.emplace());
      case EntryField::ack_time_returned:
        if (null) {
          out.ack_time_returned.reset();
          return true;
        }
        return decoder.read_u64(value, out.ack_time_returned.emplace());
      case EntryField::ack_time_mac_returned:
        if (null) {
          out.ack_time_mac_returned.reset();
          return true;
        }
        return decoder.read_u32(value, out.ack_time_mac_returned.emplace());
      case EntryField::unknown: break;
    }
    return true;  // unknown fields are ignored
  });
}

bool read_client(Decoder& decoder, std::size_t index, ClientOcpShared& out) {
  std::size_t hint = 0;
  return decoder.for_each_member(index, [&](std::string_view key, std::size_t value) {
    const ClientField field = client_fields.find(key, hint);
    const bool null = decoder.is_null(value);
    switch (field) {
      case ClientField::active_vehicle:
        if (null) {
          out.active_vehicle.reset();
          return true;
        }
        return decoder.read_string(value, out.active_vehicle.emplace());
      case ClientField::client_user_data:
        out.client_user_data.clear();
        if (null) return true;
        return decoder.for_each_member(value, [&](std::string_view name, std::size_t entry) {
          ClientVehicleEntry& target = out.client_user_data[std::string(name)];
          target = ClientVehicleEntry{};  // a repeated name: the last one wins
          return read_entry(decoder, entry, target);
        });
      case ClientField::unknown: break;
    }
    return true;  // unknown fields are ignored
  });
}

}  // namespace

Result<ClientOcpShared> decode_client_ocp_shared(std::string_view json) {
  return json_detail::decode_document<ClientOcpShared>(json, read_client);
}

void encode_client_ocp_shared(const ClientOcpShared& message, std::string& out) {
  json_detail::JsonWriter writer(out);
  writer.literal('{');
  if (message.active_vehicle) {
    writer.literal("\"active_vehicle\":");
    writer.string(*message.active_vehicle);
    writer.literal(',');
  }
  writer.literal("\"client_user_data\":{");
  bool first_vehicle = true;
  for (const auto& [name, entry] : message.client_user_data) {
    if (!first_vehicle) writer.literal(',');
    first_vehicle = false;
    writer.string(name);
    writer.literal(":{");
    bool first_field = true;
    const auto field = [&](std::string_view key) {
      writer.literal(first_field ? "\"" : ",\"");
      first_field = false;
      writer.literal(key);
      writer.literal("\":");
    };
    if (entry.user_data) {
      field("user_data");
      writer.raw(*entry.user_data);
    }
    if (entry.ocp_disable_gamepad) {
      field("ocp_disable_gamepad");
      writer.boolean(*entry.ocp_disable_gamepad);
    }
    if (entry.ack_time_returned) {
      field("ack_time_returned");
      writer.u64(*entry.ack_time_returned);
    }
    if (entry.ack_time_mac_returned) {
      field("ack_time_mac_returned");
      writer.u64(*entry.ack_time_mac_returned);
    }
    writer.literal('}');
  }
  writer.literal("}}");
}

}  // namespace ocp
