// The Observer's view of the operator side (observer.hpp): the watched fields of the Player's
// VehicleOcpShared (SPEC §4.1), as sent to the :4001 client, kept as a series of changes.
// Decoded only when an expectation watches a field, once a frame for all of them.
#include <rapidjson/document.h>
#include <rapidjson/stringbuffer.h>
#include <rapidjson/writer.h>

#include <charconv>

#include "scenario/observer.hpp"

namespace ocp::scenario {
namespace {

// One step of a dotted path: a member of an object, or an index into an array ("0", "1", …).
const rapidjson::Value* feedback_step(const rapidjson::Value& at, std::string_view name) {
  if (at.IsObject()) {
    const auto member = at.FindMember(rapidjson::Value(rapidjson::StringRef(name.data(), name.size())));
    return member == at.MemberEnd() ? nullptr : &member->value;
  }
  if (at.IsArray()) {
    std::size_t index = 0;
    const auto [end, error] = std::from_chars(name.data(), name.data() + name.size(), index);
    if (error != std::errc{} || end != name.data() + name.size() || index >= at.Size()) return nullptr;
    return &at[static_cast<rapidjson::SizeType>(index)];
  }
  return nullptr;
}

// The field's compact JSON in the vehicle's entry, or "" when it is not there.
std::string feedback_field_json(const rapidjson::Value& entry, std::string_view field) {
  const rapidjson::Value* at = &entry;
  while (at != nullptr) {
    const auto dot = field.find('.');
    at = feedback_step(*at, field.substr(0, dot));
    if (dot == std::string_view::npos) break;
    field.remove_prefix(dot + 1);
  }
  if (at == nullptr) return {};
  rapidjson::StringBuffer buffer;
  rapidjson::Writer<rapidjson::StringBuffer> writer(buffer);
  at->Accept(writer);
  return std::string(buffer.GetString(), buffer.GetSize());
}

}  // namespace

std::string feedback_key(std::string_view vehicle, std::string_view field) {
  return std::string(vehicle).append("\n").append(field);
}

void Observer::on_feedback_frame(const WireFrame& frame, SimTime now) {
  rapidjson::Document document;
  document.Parse(frame.payload.data(), frame.payload.size());
  if (document.HasParseError() || !document.IsObject()) return;   // the Player writes only what it encodes
  const auto vehicles = document.FindMember("vehicle_feedback");
  for (const FeedbackWatch& watch : options_.feedback_watches) {
    std::string value;
    if (vehicles != document.MemberEnd() && vehicles->value.IsObject()) {
      const auto entry = vehicles->value.FindMember(rapidjson::StringRef(watch.vehicle.data(), watch.vehicle.size()));
      if (entry != vehicles->value.MemberEnd()) value = feedback_field_json(entry->value, watch.field);
    }
    FeedbackSeries& series = observations_.feedback[feedback_key(watch.vehicle, watch.field)];
    ++series.frames;
    if (!series.changes.empty() && series.changes.back().json == value) continue;
    if (series.changes.size() >= feedback_change_limit) {
      series.truncated = true;
      continue;
    }
    series.changes.push_back({now, std::move(value)});
  }
}

}  // namespace ocp::scenario
