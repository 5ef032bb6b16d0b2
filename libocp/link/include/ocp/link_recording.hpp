#pragma once
// A link recording (docs/link-recording.md): what happened to each message of each direction
// of one vehicle's com channel in a recorded run — its one-way delay, or its loss — in send
// order. `ocp_scenario extract-link` writes one from a run's trace.jsonl; a link direction
// whose impairments name one (Impairments::replay) replays it: the n-th message it sends gets
// the n-th recorded outcome of its route, and after the last one the recording loops.
// Sans-IO: text in, values out; no clock. Immutable once parsed, shared by both directions.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "ocp/error.hpp"
#include "ocp/events.hpp"
#include "ocp/time.hpp"

namespace ocp {

// One message's outcome on the recorded link.
struct RecordedMessage {
  Micros sent_at{0};   // when it was sent, from the recorded run's start (for people and plots)
  Micros delay{0};     // one-way delay; meaningless when lost
  bool lost = false;
};

class LinkRecording {
 public:
  static constexpr int format_version = 1;
  static constexpr std::string_view magic = "ocp-link-recording";
  static constexpr std::size_t max_messages = 20'000'000;        // bounds memory (~500 MB)
  static constexpr std::int64_t max_delay_us = 3'600'000'000;    // one hour
  // How a route's delays were obtained (the `clock` line of the file).
  enum class Clock : std::uint8_t { measured, rtt_half };

  LinkRecording() = default;
  // Errors are "NAME:LINE: reason" (or "NAME: reason" for the file as a whole), in `detail`.
  static Result<LinkRecording> parse(std::string_view text, const std::string& name);
  // Reading the file is the app layer's job: sim_app::load_link_recording (sim_app/file_loaders.hpp).
  // The file form (what parse reads back); `comments` become leading "# " lines.
  std::string format(const std::vector<std::string>& comments) const;

  const std::string& name() const { return name_; }
  void set_name(std::string name) { name_ = std::move(name); }
  const std::vector<RecordedMessage>& route(LinkRoute route) const { return routes_[index(route)]; }
  std::vector<RecordedMessage>& route(LinkRoute route) { return routes_[index(route)]; }
  Clock clock(LinkRoute route) const { return clocks_[index(route)]; }
  void set_clock(LinkRoute route, Clock clock) { clocks_[index(route)] = clock; }
  // The outcome of the route's message number `n` (0-based, counted from when the replay
  // started): the recording loops. The route must not be empty.
  const RecordedMessage& nth(LinkRoute route, std::uint64_t n) const {
    const auto& messages = routes_[index(route)];
    return messages[n % messages.size()];
  }

 private:
  static std::size_t index(LinkRoute route) { return route == LinkRoute::to_streamer ? 0 : 1; }
  std::array<std::vector<RecordedMessage>, 2> routes_;
  std::array<Clock, 2> clocks_{Clock::measured, Clock::measured};
  std::string name_;
};

std::string_view recording_clock_name(LinkRecording::Clock clock);

}  // namespace ocp
