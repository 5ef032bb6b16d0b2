#include "conformance/wire_log.hpp"

#include <fmt/format.h>

#include <type_traits>
#include <variant>

namespace ocp::conformance {

std::string_view wire_entry_kind_name(WireEntryKind kind) {
  switch (kind) {
    case WireEntryKind::out:
      return "out";
    case WireEntryKind::in:
      return "in";
    case WireEntryKind::opened:
      return "open";
    case WireEntryKind::closed:
      return "close";
    case WireEntryKind::refused:
      return "refuse";
    case WireEntryKind::note:
      return "note";
  }
  return "?";
}

namespace {

std::string player_change_text(const ActiveVehicleChange& change) {
  return change.vehicle ? fmt::format("Player: active vehicle '{}'", *change.vehicle)
                        : std::string("Player: no active vehicle");
}
std::string player_change_text(const SourceLocked& locked) {
  return fmt::format("Player: client data source locked: {}", client_source_name(locked.source));
}
std::string player_change_text(const SourceConflict& conflict) {
  return fmt::format("Player: client data source conflict (locked {}, offending {}): all client data stopped",
                     client_source_name(conflict.locked), client_source_name(conflict.offending));
}

}  // namespace

bool WireLog::full() {
  if (entries_.size() < wire_log_max_entries) return false;
  if (dropped_++ == 0) {
    WireLogEntry entry;
    entry.time_us = entries_.back().time_us;
    entry.text = "wire log full: later events are counted, not recorded";
    entries_.push_back(std::move(entry));
  }
  return true;
}

void WireLog::attach(EventBus& bus, Wire wire) {
  subscription_ = bus.subscribe([this, wire](const Event& event) {
    if (full()) return;
    std::visit(
        [&](const auto& body) {
          using T = std::decay_t<decltype(body)>;
          if constexpr (std::is_same_v<T, WireFrame>) {
            if (body.wire != wire) return;
            WireLogEntry entry;
            entry.time_us = event.time.count();
            entry.kind = body.direction == FrameDirection::out ? WireEntryKind::out : WireEntryKind::in;
            entry.length_prefix = body.length_prefix;
            entry.drained = body.drained;
            entry.ack = body.ack;
            entry.text = std::string(body.payload);
            entries_.push_back(std::move(entry));
          } else if constexpr (std::is_same_v<T, ConnectionEvent>) {
            if (body.wire != wire) return;
            WireLogEntry entry;
            entry.time_us = event.time.count();
            entry.text = std::string(body.peer);
            switch (body.change) {
              case ConnectionChange::opened:
                entry.kind = WireEntryKind::opened;
                break;
              case ConnectionChange::closed:
                entry.kind = WireEntryKind::closed;
                break;
              case ConnectionChange::refused:
                entry.kind = WireEntryKind::refused;
                break;
            }
            if (body.reason != nullptr) {
              entry.close_code = error_code_id(body.reason->code);
              entry.text += fmt::format(" ({}: {})", entry.close_code, body.reason->detail);
            }
            entries_.push_back(std::move(entry));
          } else if constexpr (std::is_same_v<T, ActiveVehicleChange> || std::is_same_v<T, SourceLocked> ||
                               std::is_same_v<T, SourceConflict>) {
            // What the operator client's data did to the Player: evidence for the reports.
            if (wire == Wire::operator_) note(event.time.count(), player_change_text(body));
          }
        },
        event.body);
  });
}

void WireLog::note(std::int64_t time_us, std::string text) {
  WireLogEntry entry;
  entry.time_us = time_us;
  entry.kind = WireEntryKind::note;
  entry.text = std::move(text);
  entries_.push_back(std::move(entry));
}

}  // namespace ocp::conformance
