#pragma once
// --wire-log FILE|-: every frame on the simulator's TCP APIs, in both directions, as one JSON
// line each (time, source, wire, direction, kind, length prefix, ack pair, payload) — the
// "frame" lines of the trace format (docs/trace-format.md). Written from the event stream, so
// it sees exactly what the trace sees. The file is capped (max_bytes): a long run cannot fill
// the disk; reaching the cap is said once, in the log and as a last line.
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

#include "ocp/error.hpp"
#include "ocp/event_bus.hpp"
#include "ocp/log.hpp"

namespace ocp::sim_app {

inline constexpr std::uint64_t default_wire_log_max_bytes = 1024ull * 1024 * 1024;  // 1 GiB

class WireLog {
 public:
  // "-" writes to stderr. Fails (with the reason) when the file cannot be opened for writing.
  [[nodiscard]] static Result<std::unique_ptr<WireLog>> open(const std::string& path, EventBus& events,
                                                            Logger logger,
                                                            std::uint64_t max_bytes = default_wire_log_max_bytes);
  ~WireLog();
  WireLog(const WireLog&) = delete;
  WireLog& operator=(const WireLog&) = delete;

  std::uint64_t frames_written() const { return frames_written_; }

 private:
  WireLog(std::FILE* file, bool owned, Logger logger, std::uint64_t max_bytes);
  void write(const Event& event);

  std::FILE* file_;
  bool owned_;
  Logger logger_;
  std::uint64_t max_bytes_;
  std::uint64_t bytes_written_ = 0;
  std::uint64_t frames_written_ = 0;
  bool full_ = false;
  std::string line_;
  EventBus::Subscription subscription_;
};

}  // namespace ocp::sim_app
