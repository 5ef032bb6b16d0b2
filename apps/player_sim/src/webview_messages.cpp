// The web view envelope: parsing and building {"name": …, "data": …} with RapidJSON.
#include <rapidjson/document.h>
#include <rapidjson/error/en.h>
#include <rapidjson/stringbuffer.h>
#include <rapidjson/writer.h>

#include <fmt/format.h>

#include "player_app/webview/messages.hpp"
#include "player/player_core.hpp"

namespace ocp::webview {
namespace {

Error malformed(std::string detail) {
  return Error{make_error_code(PeerError::malformed_json), std::move(detail)};
}

void write_string(rapidjson::Writer<rapidjson::StringBuffer>& writer, std::string_view text) {
  writer.String(text.data(), static_cast<rapidjson::SizeType>(text.size()));
}

}  // namespace

Result<InboundMessage> parse_envelope(std::string_view text) {
  rapidjson::Document document;
  // Iterative parsing: nesting depth cannot exhaust the stack (the message is ≤ 64 KiB).
  document.Parse<rapidjson::kParseIterativeFlag | rapidjson::kParseValidateEncodingFlag>(text.data(), text.size());
  if (document.HasParseError()) {
    return malformed(std::string("not JSON: ") + rapidjson::GetParseError_En(document.GetParseError()) +
                     " at offset " + std::to_string(document.GetErrorOffset()));
  }
  if (!document.IsObject()) return Error{make_error_code(PeerError::not_an_object), "expected {\"name\": …, \"data\": …}"};
  const auto name = document.FindMember("name");
  if (name == document.MemberEnd()) return Error{make_error_code(PeerError::missing_field), "name: missing"};
  if (!name->value.IsString()) return Error{make_error_code(PeerError::wrong_type), "name: expected string"};
  const auto data = document.FindMember("data");
  if (data == document.MemberEnd()) return Error{make_error_code(PeerError::missing_field), "data: missing"};
  InboundMessage message;
  message.name.assign(name->value.GetString(), name->value.GetStringLength());
  rapidjson::StringBuffer buffer;
  rapidjson::Writer<rapidjson::StringBuffer> writer(buffer);
  data->value.Accept(writer);
  message.data_json.assign(buffer.GetString(), buffer.GetSize());
  return message;
}

std::string make_envelope(std::string_view name, std::string_view data_json) {
  std::string out;
  out.reserve(name.size() + data_json.size() + 20);
  out += "{\"name\":\"";
  out += name;   // our own constant names: no escaping needed
  out += "\",\"data\":";
  out += data_json;
  out += '}';
  return out;
}

bool is_keep_alive(const ClientOcpShared& data) { return ocp::is_keep_alive(ClientSource::webview, data); }

std::string describe(const Status::ClientFrameTooLarge& too_large) {
  return fmt::format("VehicleOcpShared too large: {} B > {} B, not sent to the operator TCP client, which "
                     "receives nothing until it fits. Reduce the vehicles ({}), their vehicle_user_data or cameras.",
                     too_large.bytes, too_large.limit, too_large.vehicles);
}

Status::ClientFrameTooLarge status_of(const ocp::ClientFrameTooLarge& too_large) {
  return Status::ClientFrameTooLarge{too_large.bytes, too_large.limit, too_large.vehicles};
}

std::string encode_status(const Status& status) {
  rapidjson::StringBuffer buffer;
  rapidjson::Writer<rapidjson::StringBuffer> writer(buffer);
  writer.StartObject();
  writer.Key("locked_source");
  if (status.locked_source) write_string(writer, *status.locked_source); else writer.Null();
  writer.Key("client_data_stopped");
  writer.Bool(status.client_data_stopped);
  writer.Key("active_vehicle");
  if (status.active_vehicle) write_string(writer, *status.active_vehicle); else writer.Null();
  writer.Key("vehicles");
  writer.StartArray();
  for (const auto& vehicle : status.vehicles) write_string(writer, vehicle);
  writer.EndArray();
  writer.Key("webview_clients");
  writer.Uint64(status.webview_clients);
  // {"bytes": 19574, "limit": 16384, "vehicles": 20, "text": "…"}; absent while it fits.
  if (const auto& too_large = status.client_frame_too_large) {
    writer.Key("client_frame_too_large");
    writer.StartObject();
    writer.Key("bytes");
    writer.Uint64(too_large->bytes);
    writer.Key("limit");
    writer.Uint64(too_large->limit);
    writer.Key("vehicles");
    writer.Uint64(too_large->vehicles);
    writer.Key("text");
    write_string(writer, describe(*too_large));
    writer.EndObject();
  }
  if (status.tcp_lock_without_client) {
    writer.Key("tcp_lock_without_client");
    write_string(writer, *status.tcp_lock_without_client);
  }
  writer.Key("loop_not_closed");
  writer.StartObject();
  for (const auto& [vehicle, hint] : status.loop_not_closed) {
    write_string(writer, vehicle);   // a Key: the writer takes a string in key position
    write_string(writer, hint);
  }
  writer.EndObject();
  writer.EndObject();
  return {buffer.GetString(), buffer.GetSize()};
}

std::string encode_error(std::string_view kind, std::string_view detail) {
  rapidjson::StringBuffer buffer;
  rapidjson::Writer<rapidjson::StringBuffer> writer(buffer);
  writer.StartObject();
  writer.Key("kind");
  write_string(writer, kind);
  writer.Key("detail");
  write_string(writer, detail);
  writer.EndObject();
  return {buffer.GetString(), buffer.GetSize()};
}

}  // namespace ocp::webview
