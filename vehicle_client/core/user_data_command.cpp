// Commands in client_user_data, used when the operator disabled gamepad forwarding
// (controller: null). The operator-side client decides the shape; this reference client
// accepts {"throttle": 0..1, "brake": 0..1, "steer": -1..1, "enable": true|false}.
#include <rapidjson/document.h>
#include <rapidjson/error/en.h>

#include "vehicle_client/safety_layer.hpp"

namespace ocp {
namespace {

std::optional<double> number_field(const rapidjson::Value& object, const char* name) {
  const auto member = object.FindMember(name);
  if (member == object.MemberEnd() || !member->value.IsNumber()) return std::nullopt;
  return member->value.GetDouble();
}

}  // namespace

std::optional<UserDataCommand> parse_user_data_command(std::string_view json) {
  rapidjson::Document document;
  // Depth is bounded by the codec (it validated this text when decoding the message).
  document.Parse<rapidjson::kParseStopWhenDoneFlag>(json.data(), json.size());
  if (document.HasParseError() || !document.IsObject()) return std::nullopt;

  UserDataCommand command;
  command.throttle = number_field(document, "throttle");
  command.brake = number_field(document, "brake");
  command.steer = number_field(document, "steer");
  const auto enable = document.FindMember("enable");
  if (enable != document.MemberEnd() && enable->value.IsBool()) command.enable = enable->value.GetBool();
  if (!command.has_motion() && !command.enable) return std::nullopt;
  return command;
}

}  // namespace ocp
