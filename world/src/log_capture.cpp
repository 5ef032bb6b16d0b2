#include "world/log_capture.hpp"

#include <fmt/format.h>

#include <iterator>

namespace ocp {

LogSink LogCapture::sink() {
  return [this](const LogRecord& record) {
    fmt::format_to(std::back_inserter(text_), "{:>12} {} {}: {}\n", record.time.count(),
                   record.component, log_level_name(record.level), record.message);
  };
}

std::vector<std::string> lines_containing(std::string_view text, std::string_view needle) {
  std::vector<std::string> found;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line(text.data() + start, end - start);
    if (line.find(needle) != std::string_view::npos) found.emplace_back(line);
    start = end + 1;
  }
  return found;
}

}  // namespace ocp
