#pragma once
// TraceRecorder: the trace of a run as JSON Lines — one event of the event stream per line,
// with stable field names (docs/trace-format.md, format version trace_format_version). It
// subscribes to an EventBus (usually World::events()); log lines are not part of it, so
// rewording a log message never changes a trace. In virtual time the same seed gives the
// same trace byte for byte: determinism is asserted by comparing traces (or their digests,
// kept even when the lines are not). The human-readable text form is rendered from the JSON
// Lines (render_trace_text), never written separately.
#include <cstdint>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "ocp/event_bus.hpp"
#include "ocp/time.hpp"

namespace ocp {

inline constexpr int trace_format_version = 1;

struct TraceOptions {
  bool keep_lines = true;        // false: only the digest and line count (long runs)
  // Where each line is also written as it is recorded (a file: a run of hours then holds no
  // line in memory); nullptr: nowhere. Must outlive the recorder.
  std::ostream* stream = nullptr;
  bool frames = true;            // WireFrame events (every frame on both TCP APIs)
  bool frame_payloads = true;    // … with their payload bytes
  bool link_messages = true;     // LinkEvent per com-channel message sent / delivered / dropped
  bool latency_samples = true;   // LatencySample per Streamer control tick
};

// One event as one JSON line (with its '\n'), appended to `out`. Fields: docs/trace-format.md.
void append_trace_line(const Event& event, const TraceOptions& options, std::string& out);
// The first line of every trace: {"t_us":0,"source":"trace","event":"trace_format","version":N}.
std::string trace_header_line();

// The text form, one line per JSON line: "<time µs, 12 wide> <source> <what happened>".
// Lines that are not trace JSON are rendered as "? <line>" (never dropped silently).
std::string render_trace_text(std::string_view jsonl);

class TraceRecorder {
 public:
  TraceRecorder(EventBus& bus, TraceOptions options = {});
  TraceRecorder(const TraceRecorder&) = delete;
  TraceRecorder& operator=(const TraceRecorder&) = delete;

  const std::string& jsonl() const { return jsonl_; }   // empty unless keep_lines
  std::string text() const { return render_trace_text(jsonl_); }
  std::uint64_t digest() const { return digest_; }     // FNV-1a over every line recorded
  std::uint64_t lines() const { return lines_; }
  // JSON lines containing `needle` (for assertions); needs keep_lines.
  std::vector<std::string> lines_containing(std::string_view needle) const;
  // The "t_us" of one of its lines.
  static SimTime line_time(std::string_view line);

 private:
  void append(const std::string& line);

  TraceOptions options_;
  std::string jsonl_;
  std::string line_;   // reused buffer for one line
  std::uint64_t digest_;
  std::uint64_t lines_ = 0;
  EventBus::Subscription subscription_;
};

}  // namespace ocp
