#pragma once
// Logging for cores and fronts. Every line carries the executor's time (virtual or real), so
// a virtual-time run logs the same lines byte for byte every time. Lines go to a LogSink:
// the default one prints through spdlog; tests and scenario traces install their own.
#include <fmt/format.h>

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <utility>

#include "ocp/executor.hpp"

namespace ocp {

enum class LogLevel { debug, info, warn, error };
std::string_view log_level_name(LogLevel level);
// "debug" | "info" | "warn" | "error" (also "warning"); nullopt-like false when unknown.
bool parse_log_level(std::string_view text, LogLevel& level);

struct LogRecord {
  SimTime time;
  LogLevel level;
  std::string_view component;   // "streamer:truck-1", "player", "vehicle-client", …
  std::string_view message;
};
using LogSink = std::function<void(const LogRecord&)>;

// Prints "[   12.345678] INFO  streamer:truck-1: message" through spdlog, at or above `minimum`.
// Sets spdlog's global pattern to the bare message, since the sink formats the stamp itself.
LogSink make_console_sink(LogLevel minimum = LogLevel::info);
// Drops everything (benchmarks, quiet tests).
LogSink make_null_sink();

class Logger {
 public:
  Logger(const Executor& executor, std::string component, LogSink sink)
      : executor_(&executor), component_(std::move(component)), sink_(std::move(sink)) {}

  template <class... Args>
  void debug(fmt::format_string<Args...> format, Args&&... args) const {
    write(LogLevel::debug, format, std::forward<Args>(args)...);
  }
  template <class... Args>
  void info(fmt::format_string<Args...> format, Args&&... args) const {
    write(LogLevel::info, format, std::forward<Args>(args)...);
  }
  template <class... Args>
  void warn(fmt::format_string<Args...> format, Args&&... args) const {
    write(LogLevel::warn, format, std::forward<Args>(args)...);
  }
  template <class... Args>
  void error(fmt::format_string<Args...> format, Args&&... args) const {
    write(LogLevel::error, format, std::forward<Args>(args)...);
  }

  const std::string& component() const { return component_; }
  // The clock the lines are stamped with (for log-rate limiting, see flap_summariser.hpp).
  SimTime now() const { return executor_->now(); }
  const LogSink& sink() const { return sink_; }
  // A logger for a sub-component sharing the same sink and clock.
  Logger child(std::string_view suffix) const {
    return Logger(*executor_, component_ + ":" + std::string(suffix), sink_);
  }

 private:
  template <class... Args>
  void write(LogLevel level, fmt::format_string<Args...> format, Args&&... args) const {
    if (!sink_) return;
    const std::string message = fmt::format(format, std::forward<Args>(args)...);
    sink_(LogRecord{executor_->now(), level, component_, message});
  }

  const Executor* executor_;
  std::string component_;
  LogSink sink_;
};

}  // namespace ocp
