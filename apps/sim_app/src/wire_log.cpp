#include "sim_app/wire_log.hpp"

#include <cerrno>
#include <cstring>

#include "world/trace.hpp"

namespace ocp::sim_app {

Result<std::unique_ptr<WireLog>> WireLog::open(const std::string& path, EventBus& events, Logger logger,
                                               std::uint64_t max_bytes) {
  if (path.empty()) return Error{std::make_error_code(std::errc::invalid_argument), "an empty path"};
  std::FILE* file = path == "-" ? stderr : std::fopen(path.c_str(), "w");
  if (file == nullptr) {
    return Error{std::error_code(errno, std::generic_category()),
                 "cannot write '" + path + "': " + std::strerror(errno)};
  }
  std::unique_ptr<WireLog> log(new WireLog(file, path != "-", std::move(logger), max_bytes));
  WireLog* raw = log.get();
  log->subscription_ = events.subscribe([raw](const Event& event) { raw->write(event); });
  return log;
}

WireLog::WireLog(std::FILE* file, bool owned, Logger logger, std::uint64_t max_bytes)
    : file_(file), owned_(owned), logger_(std::move(logger)), max_bytes_(max_bytes) {}

WireLog::~WireLog() {
  subscription_.reset();
  if (owned_) {
    std::fclose(file_);
  } else {
    std::fflush(file_);
  }
}

void WireLog::write(const Event& event) {
  if (full_ || !std::holds_alternative<WireFrame>(event.body)) return;
  TraceOptions frames_only;
  line_.clear();
  append_trace_line(event, frames_only, line_);
  if (bytes_written_ + line_.size() > max_bytes_) {
    full_ = true;
    logger_.warn("wire log reached its limit of {} bytes after {} frames; no more frames are written",
                 max_bytes_, frames_written_);
    std::fputs("{\"event\":\"wire_log_full\"}\n", file_);
    std::fflush(file_);
    return;
  }
  std::fwrite(line_.data(), 1, line_.size(), file_);
  bytes_written_ += line_.size();
  ++frames_written_;
}

}  // namespace ocp::sim_app
