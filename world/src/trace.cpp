#include "world/trace.hpp"

#include "world/log_capture.hpp"

#include <string>

namespace ocp {
namespace {

constexpr std::uint64_t fnv_offset = 0xcbf29ce484222325ull;
constexpr std::uint64_t fnv_prime = 0x100000001b3ull;

}  // namespace

TraceRecorder::TraceRecorder(EventBus& bus, TraceOptions options)
    : options_(options), digest_(fnv_offset) {
  append(trace_header_line());
  subscription_ = bus.subscribe([this](const Event& event) {
    line_.clear();
    append_trace_line(event, options_, line_);
    if (!line_.empty()) append(line_);
  });
}

void TraceRecorder::append(const std::string& line) {
  for (const char character : line) {
    digest_ = (digest_ ^ static_cast<unsigned char>(character)) * fnv_prime;
  }
  ++lines_;
  if (options_.keep_lines) jsonl_ += line;
  if (options_.stream != nullptr) options_.stream->write(line.data(), static_cast<std::streamsize>(line.size()));
}

std::vector<std::string> TraceRecorder::lines_containing(std::string_view needle) const {
  return ocp::lines_containing(jsonl_, needle);
}

SimTime TraceRecorder::line_time(std::string_view line) {
  // Every line starts with {"t_us":N (docs/trace-format.md).
  constexpr std::string_view prefix = "{\"t_us\":";
  if (line.substr(0, prefix.size()) != prefix) return SimTime{-1};
  std::int64_t value = 0;
  for (std::size_t i = prefix.size(); i < line.size() && line[i] >= '0' && line[i] <= '9'; ++i) {
    value = value * 10 + (line[i] - '0');
  }
  return SimTime{value};
}

}  // namespace ocp
