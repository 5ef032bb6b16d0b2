#include "ocp/log.hpp"

#include <spdlog/spdlog.h>

namespace ocp {

std::string_view log_level_name(LogLevel level) {
  switch (level) {
    case LogLevel::debug: return "DEBUG";
    case LogLevel::info: return "INFO";
    case LogLevel::warn: return "WARN";
    case LogLevel::error: return "ERROR";
  }
  return "?";
}

bool parse_log_level(std::string_view text, LogLevel& level) {
  if (text == "debug") level = LogLevel::debug;
  else if (text == "info") level = LogLevel::info;
  else if (text == "warn" || text == "warning") level = LogLevel::warn;
  else if (text == "error") level = LogLevel::error;
  else return false;
  return true;
}

LogSink make_console_sink(LogLevel minimum) {
  // The sink writes the time stamp, level and component itself; spdlog only prints the line
  // (and flushes it at once, so a person watching sees events as they happen).
  spdlog::set_pattern("%v");
  spdlog::set_level(spdlog::level::debug);
  spdlog::flush_on(spdlog::level::debug);
  return [minimum](const LogRecord& record) {
    if (record.level < minimum) return;
    const double seconds = static_cast<double>(record.time.count()) / 1e6;
    const auto line = fmt::format("[{:12.6f}] {:<5} {}: {}", seconds, log_level_name(record.level),
                                  record.component, record.message);
    switch (record.level) {
      case LogLevel::debug: spdlog::debug("{}", line); break;
      case LogLevel::info: spdlog::info("{}", line); break;
      case LogLevel::warn: spdlog::warn("{}", line); break;
      case LogLevel::error: spdlog::error("{}", line); break;
    }
  };
}

LogSink make_null_sink() { return {}; }

}  // namespace ocp
