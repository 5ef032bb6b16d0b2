// `operator/4.3/2`'s second half (issue #35): vehicle_feedback is a map (seed 004: a hashmap),
// and JSON object order is not significant, so the product may list the vehicles in any
// order, and in another order in the next frame. Hand-made frames give each control vehicle a
// pair of its own, the vehicles listed in reverse order every other frame: a client that maps
// vehicles by position returns one vehicle's pair for another.
#include <rapidjson/document.h>
#include <rapidjson/stringbuffer.h>
#include <rapidjson/writer.h>

#include "case_helpers.hpp"
#include "conformance/control_frames.hpp"
#include "ocp/json_codec.hpp"
#include "operator_observations.hpp"

namespace ocp::conformance::detail {
namespace {

// The same JSON with vehicle_feedback's members in reverse order (numbers stay exact: u64 is
// parsed and written as an integer).
std::string reverse_vehicle_order(const std::string& json) {
  rapidjson::Document document;
  document.Parse(json.data(), json.size());
  if (document.HasParseError() || !document.IsObject()) return json;
  auto feedback = document.FindMember("vehicle_feedback");
  if (feedback == document.MemberEnd() || !feedback->value.IsObject()) return json;
  rapidjson::Value reversed(rapidjson::kObjectType);
  auto& allocator = document.GetAllocator();
  std::vector<rapidjson::Value*> names, values;
  for (auto& member : feedback->value.GetObject()) {
    names.push_back(&member.name);
    values.push_back(&member.value);
  }
  for (std::size_t i = names.size(); i-- > 0;)
    reversed.AddMember(rapidjson::Value(*names[i], allocator), rapidjson::Value(*values[i], allocator), allocator);
  feedback->value = reversed;
  rapidjson::StringBuffer buffer;
  rapidjson::Writer<rapidjson::StringBuffer> writer(buffer);
  document.Accept(writer);
  return std::string(buffer.GetString(), buffer.GetSize());
}

bool returned_for(const OperatorObservations& observed, const std::string& vehicle, const AckPair& pair,
                  std::int64_t since_us) {
  const auto found = observed.returned.find(vehicle);
  if (found == observed.returned.end()) return false;
  for (const SentPair& back : found->second) {
    if (back.time_us >= since_us && back.ack == pair) return true;
  }
  return false;
}

}  // namespace

Outcome grade_reordered_vehicles(CaseContext& context) {
  PlayerCore& player = context.host().player();
  std::vector<std::string> control;
  for (const HostedVehicle& vehicle : context.host().vehicles()) {
    if (!vehicle.monitor) control.push_back(vehicle.name);
  }
  player.set_client_output_paused(true);
  context.run_for(milliseconds(20));  // answers to the last real frames arrive
  const std::int64_t start = context.now_us();
  constexpr std::size_t frames = 12;
  std::map<std::string, std::vector<AckPair>> sent;
  for (std::size_t i = 0; i < frames && player.client_connected(); ++i) {
    VehicleOcpShared shared = player.last_shared();
    for (std::size_t v = 0; v < control.size(); ++v) {
      sent[control[v]].push_back(crafted_pair(91 + v, i));
      shared.vehicle_feedback[control[v]].ack = sent[control[v]].back();
    }
    std::string json;
    encode_vehicle_ocp_shared(shared, json);
    if (i % 2 == 1) json = reverse_vehicle_order(json);
    (void)player.write_raw_to_client(frame_bytes(json));
    context.run_for(milliseconds(15));
  }
  context.run_for(milliseconds(300));
  player.set_client_output_paused(false);
  const OperatorObservations observed = OperatorObservations::from(context.entries());
  const std::string what = fmt::format(
      "{} frames with each control vehicle's own pair, every other one listing the vehicles in "
      "reverse order (seed 004: a hashmap; JSON order is not significant)",
      frames);
  for (std::size_t i = 0; i < observed.closed_us.size(); ++i) {
    if (observed.closed_us[i] >= start) return failed(what + "; the connection closed: " + observed.close_codes[i]);
  }
  // Any name the client returned pairs under (a monitor's too): never another vehicle's pair.
  for (const auto& [vehicle, returns] : observed.returned) {
    for (const auto& [other, pairs] : sent) {
      if (other == vehicle) continue;
      for (const AckPair& p : pairs) {
        if (returned_for(observed, vehicle, p, start)) {
          return failed(fmt::format(
              "{}; '{}' was returned the pair {} of '{}': vehicles mapped by their position, not their name", what,
              vehicle, describe(p), other));
        }
      }
    }
  }
  // The last frame in each order: every control vehicle's own pair back under its name.
  for (const std::string& vehicle : control) {
    const auto& own = sent[vehicle];
    for (std::size_t back = 1; back <= 2 && back <= own.size(); ++back) {
      if (!returned_for(observed, vehicle, own[own.size() - back], start)) {
        return failed(fmt::format("{}; '{}' never returned its pair {} of the last frame {}", what, vehicle,
                                  describe(own[own.size() - back]),
                                  back == 1 ? "(vehicles in reverse order)" : "(in name order)"));
      }
    }
  }
  return ok(what + ": every vehicle's own pair returned");
}

}  // namespace ocp::conformance::detail
