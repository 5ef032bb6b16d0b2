#include "operator_observations.hpp"

#include <rapidjson/document.h>
#include <rapidjson/stringbuffer.h>
#include <rapidjson/writer.h>

#include <fmt/format.h>

#include <algorithm>
#include <variant>

#include "ocp/json_codec.hpp"

namespace ocp::conformance::detail {

OperatorObservations OperatorObservations::from(const std::vector<WireLogEntry>& entries, std::int64_t since_us) {
  OperatorObservations observed;
  for (const WireLogEntry& e : entries) {
    if (e.time_us < since_us) continue;
    switch (e.kind) {
      case WireEntryKind::out:
        if (auto shared = decode_vehicle_ocp_shared(e.text)) {
          for (const auto& [name, feedback] : shared->vehicle_feedback) {
            observed.linked.insert(name);
            if (feedback.is_monitor) observed.monitors.insert(name);
            observed.published[name].push_back({e.time_us, feedback.ack});
          }
        }
        break;
      case WireEntryKind::in: {
        observed.client_frames_us.push_back(e.time_us);
        observed.drained += e.drained;
        auto data = decode_client_ocp_shared(e.text);
        if (!data) break;
        if (data->active_vehicle) observed.active_vehicle.push_back({e.time_us, "", *data->active_vehicle});
        for (const auto& [name, entry] : data->client_user_data) {
          if (entry.ack_time_returned && entry.ack_time_mac_returned) {
            observed.returned[name].push_back(
                {e.time_us, AckPair{*entry.ack_time_returned, *entry.ack_time_mac_returned}});
          }
          if (entry.user_data) observed.user_data.push_back({e.time_us, name, compact_json(entry.user_data->text)});
          observed.gamepad.push_back({e.time_us, name, entry.ocp_disable_gamepad});
        }
        break;
      }
      case WireEntryKind::opened:
        observed.opened_us.push_back(e.time_us);
        break;
      case WireEntryKind::closed:
        observed.closed_us.push_back(e.time_us);
        observed.close_codes.push_back(e.close_code);
        break;
      case WireEntryKind::refused:
        ++observed.refused;
        break;
      case WireEntryKind::note:
        break;
    }
  }
  return observed;
}

std::int64_t OperatorObservations::find_published(const std::string& vehicle, const AckPair& pair) const {
  const auto found = published.find(vehicle);
  if (found == published.end()) return -1;
  for (std::size_t i = found->second.size(); i-- > 0;) {
    if (found->second[i].ack == pair) return static_cast<std::int64_t>(i);
  }
  return -1;
}

bool OperatorObservations::closed_by_peer_error() const {
  return std::any_of(close_codes.begin(), close_codes.end(),
                     [](const std::string& code) { return code.rfind("peer.", 0) == 0; });
}

PairReturns pair_returns(const OperatorObservations& observed, const std::string& vehicle) {
  PairReturns returns;
  const auto returned = observed.returned.find(vehicle);
  if (returned == observed.returned.end()) return returns;
  static const std::vector<SentPair> never;
  const auto found = observed.published.find(vehicle);
  const std::vector<SentPair>& published = found == observed.published.end() ? never : found->second;
  for (const SentPair& pair : published) returns.published.push_back(pair.ack);
  for (const SentPair& back : returned->second) {
    ++returns.count;
    const std::int64_t index = observed.find_published(vehicle, back.ack);
    if (index < 0) {
      returns.altered.push_back(back.ack);
      continue;
    }
    // Behind = how long before this return a newer pair had already been published.
    for (std::size_t i = static_cast<std::size_t>(index) + 1;
         i < published.size() && published[i].time_us <= back.time_us; ++i) {
      if (!(published[i].ack == back.ack)) {
        if (back.time_us - published[i].time_us > 500'000) ++returns.stale;
        break;
      }
    }
  }
  return returns;
}

std::string PairReturns::describe(const std::string& vehicle) const {
  return fmt::format("'{}': {} returned pairs, {} altered, {} stale (> 500 ms behind)", vehicle, count, altered.size(),
                     stale);
}

StreamerSetup operator_setup() {
  StreamerSetup setup;
  setup.operator_side = true;
  return setup;
}

StreamerSetup fleet_setup() {
  StreamerSetup setup = operator_setup();
  setup.fleet = {{fleet_monitor, true}, {"truck-1", false}, {"truck-2", false}};
  return setup;
}

std::string compact_json(std::string_view json) {
  rapidjson::Document document;
  document.Parse(json.data(), json.size());
  if (document.HasParseError()) return std::string(json);
  rapidjson::StringBuffer buffer;
  rapidjson::Writer<rapidjson::StringBuffer> writer(buffer);
  document.Accept(writer);
  return std::string(buffer.GetString(), buffer.GetSize());
}

VehicleWireWatch::VehicleWireWatch(StreamerHost& host) {
  for (const HostedVehicle& vehicle : host.vehicles()) {
    if (vehicle.monitor) continue;
    std::vector<ControlSeen>& seen = seen_[vehicle.name];
    subscriptions_.push_back(host.streamer(vehicle.name).events().subscribe([&seen](const Event& event) {
      const auto* frame = std::get_if<WireFrame>(&event.body);
      if (frame == nullptr || frame->wire != Wire::vehicle || frame->direction != FrameDirection::out ||
          frame->kind != WireMessageKind::control || seen.size() >= max_per_vehicle) {
        return;
      }
      auto control = decode_control_message(frame->payload);
      if (!control) return;
      ControlSeen entry;
      entry.time_us = event.time.count();
      entry.controller_null = !control->controller.has_value();
      if (control->client_user_data) entry.user_data = compact_json(control->client_user_data->text);
      seen.push_back(std::move(entry));
    }));
  }
}

const std::vector<ControlSeen>& VehicleWireWatch::seen(const std::string& vehicle) const {
  static const std::vector<ControlSeen> none;
  const auto found = seen_.find(vehicle);
  return found == seen_.end() ? none : found->second;
}

}  // namespace ocp::conformance::detail
