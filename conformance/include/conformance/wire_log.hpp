#pragma once
// The wire log of one case: every control frame out and response in (time, length prefix,
// payload, pair), every connection change and a few harness notes — built only from the
// Streamer's event stream (StreamerCore::events()), never from hooks in the core.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ocp/event_bus.hpp"
#include "ocp/messages.hpp"

namespace ocp::conformance {

enum class WireEntryKind { out, in, opened, closed, refused, note };
std::string_view wire_entry_kind_name(WireEntryKind kind);  // "out" | "in" | "open" | …

struct WireLogEntry {
  std::int64_t time_us = 0;  // the host executor's µs (one timeline per host)
  WireEntryKind kind = WireEntryKind::note;
  std::uint32_t length_prefix = 0;  // out / in
  bool drained = false;             // in: oversized frame the Streamer skipped
  std::optional<AckPair> ack;       // the pair the frame carries, when it decodes
  std::string text;                 // payload (out / in), peer + reason (connections), note
  std::string close_code;           // closed: "peer.read_timeout", "local.shut_down", …
};

// A flooding client could grow a log without bound: past this many entries only a count is
// kept (a conforming client stays far below it: ~200 frames a second each way).
inline constexpr std::size_t wire_log_max_entries = 100'000;

class WireLog {
 public:
  // Records everything `bus` publishes about `wire` from now on (replaces any previous
  // subscription: a restarted Streamer has a new bus). On the operator wire the Player's
  // active-vehicle and source-lock changes are noted too.
  void attach(EventBus& bus, Wire wire = Wire::vehicle);
  void detach() { subscription_.reset(); }
  void note(std::int64_t time_us, std::string text);

  const std::vector<WireLogEntry>& entries() const { return entries_; }
  std::size_t dropped() const { return dropped_; }
  std::vector<WireLogEntry> take() { return std::move(entries_); }

 private:
  EventBus::Subscription subscription_;
  bool full();
  std::vector<WireLogEntry> entries_;
  std::size_t dropped_ = 0;
};

}  // namespace ocp::conformance
