// Scenario files: `replay: FILE` in a link's impairments (docs/link-recording.md). Kept out of
// parse_world.cpp: the recording's loading, caching and checks are one concern.
#include "parser.hpp"

#include <filesystem>

#include "ocp/link_recording.hpp"
#include "scenario/parse.hpp"

namespace ocp::scenario {

std::shared_ptr<const LinkRecording> Parser::link_recording(const YAML::Node& node, const YAML::Node& fields) {
  // The recording is the whole network of that direction: other settings would go unused.
  for (const char* other : {"delay", "jitter", "jitter_kind", "loss", "burst_loss", "bandwidth_bps", "trace",
                            "queue_limit_bytes", "queue_limit_packets", "duplicate", "reorder", "reorder_extra_delay"}) {
    if (fields[other]) {
      read_.fail(fields[other], std::string("replay and ") + other +
                                    " exclude each other: the recording holds each message's delay or loss");
    }
  }
  return named_file(node, "replay", "a link recording file name", link_recordings_);
}

void Parser::check_replayed_routes(const VehicleSpec& spec, const YAML::Node& node) {
  const auto check = [&](const Impairments& set, LinkRoute route, const char* key) {
    if (!set.replay || !set.replay->route(route).empty()) return;
    // Named in the direction's own block, or else in `link`.
    const YAML::Node where = node[key] && node[key]["replay"] ? node[key]["replay"] : node["link"]["replay"];
    read_.fail(where, set.replay->name() + " has no " + std::string(link_route_name(route)) +
                          " messages to replay (replay it on the other direction only: " +
                          std::string(link_route_name(route) == "to_streamer" ? "to_player" : "to_streamer") +
                          ": {replay: FILE})");
  };
  check(spec.to_streamer, LinkRoute::to_streamer, "to_streamer");
  check(spec.to_player, LinkRoute::to_player, "to_player");
}

}  // namespace ocp::scenario
