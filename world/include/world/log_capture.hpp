#pragma once
// LogCapture: keeps a run's log lines as text ("<time µs, 12 wide> <component> <LEVEL>:
// <message>"), for tests that check what a person would read. Log lines are not the trace
// (trace.hpp): the trace holds typed events only.
#include <string>
#include <string_view>
#include <vector>

#include "ocp/log.hpp"

namespace ocp {

// The lines of `text` (separated by '\n') that contain `needle`.
std::vector<std::string> lines_containing(std::string_view text, std::string_view needle);

class LogCapture {
 public:
  // A sink that appends to this capture; the capture must outlive its use.
  LogSink sink();
  const std::string& text() const { return text_; }
  std::vector<std::string> lines_containing(std::string_view needle) const {
    return ocp::lines_containing(text_, needle);
  }

 private:
  std::string text_;
};

}  // namespace ocp
