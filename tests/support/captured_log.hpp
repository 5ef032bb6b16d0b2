#pragma once
// The one log sink of the test suites: keeps every line (time, level, component, message) so a
// test can check what a person reading the log would see. Install with `log.sink()`; the log
// must outlive every Logger holding that sink.
#include <string>
#include <string_view>
#include <vector>

#include "ocp/log.hpp"

namespace ocp::testing {

class CapturedLog {
 public:
  struct Line {
    SimTime time;
    LogLevel level;
    std::string component;
    std::string message;
  };

  LogSink sink() {
    return [this](const LogRecord& record) {
      lines_.push_back(Line{record.time, record.level, std::string(record.component),
                            std::string(record.message)});
    };
  }

  const std::vector<Line>& lines() const { return lines_; }

  // The first line at `level` whose message contains `needle`, or nullptr.
  const Line* find(LogLevel level, std::string_view needle) const {
    for (const Line& line : lines_) {
      if (line.level == level && line.message.find(needle) != std::string::npos) return &line;
    }
    return nullptr;
  }
  bool contains(LogLevel level, std::string_view needle) const { return find(level, needle) != nullptr; }
  // Any level.
  bool contains(std::string_view needle) const {
    for (const Line& line : lines_) {
      if (line.message.find(needle) != std::string::npos) return true;
    }
    return false;
  }

 private:
  std::vector<Line> lines_;
};

}  // namespace ocp::testing
