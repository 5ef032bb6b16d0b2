#pragma once
// TraceRecorder: a text event trace of a world run, one line per event:
//   "<time µs, 12 wide> <component> <event>"
// Sources: every log line (through sink()), every Streamer's fault changes, vehicle
// connections and (with `messages`) every control frame and vehicle response, and the
// Player's per-vehicle sender/receiver fault changes seen in its VehicleOcpShared. In virtual
// time the same seed gives the same trace byte for byte, so determinism is asserted by
// comparing two traces (or their digests, which are kept even when the text is not).
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "ocp/executor.hpp"
#include "ocp/log.hpp"

namespace ocp {

class World;

struct TraceOptions {
  bool keep_text = true;                 // false: only the digest and line count (long runs)
  bool messages = false;                 // also one line per control frame / vehicle response
  LogLevel minimum_log_level = LogLevel::debug;
};

class TraceRecorder {
 public:
  explicit TraceRecorder(const Executor& executor, TraceOptions options = {});
  ~TraceRecorder();
  TraceRecorder(const TraceRecorder&) = delete;
  TraceRecorder& operator=(const TraceRecorder&) = delete;

  // A LogSink that records log lines (pass it to World, or wrap it with another sink).
  LogSink sink();
  // Installs observers on the world's Streamers and Player. Before start() (preferred) this
  // goes through World::set_on_built, so the first events of the run are recorded too; after
  // start() it installs them at once. Call once. The recorder must outlive the world's run.
  void observe(World& world);

  // Appends one event (also usable by tests and scenario scripts for their own markers).
  void record(std::string_view component, std::string_view event);

  const std::string& text() const { return text_; }
  std::uint64_t digest() const { return digest_; }    // FNV-1a over every line recorded
  std::uint64_t lines() const { return lines_; }
  // Lines containing `needle` (for assertions); needs keep_text.
  std::vector<std::string> lines_containing(std::string_view needle) const;

 private:
  class StreamerWatcher;
  class PlayerWatcher;
  void append_line();
  void install(World& world);

  const Executor& executor_;
  TraceOptions options_;
  std::string text_;
  std::string line_;                     // reused buffer for one line
  std::uint64_t digest_;
  std::uint64_t lines_ = 0;
  std::vector<std::unique_ptr<StreamerWatcher>> streamer_watchers_;
  std::unique_ptr<PlayerWatcher> player_watcher_;
};

}  // namespace ocp
