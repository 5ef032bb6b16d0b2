// Small /proc files and the fields of a stat line (sim_app/proc_stat.hpp).
#include "sim_app/proc_stat.hpp"

#include <fcntl.h>
#include <unistd.h>

namespace ocp::sim_app {

std::string read_small_proc_file(const char* path, std::size_t max_bytes) {
  const int fd = open(path, O_RDONLY | O_CLOEXEC);
  if (fd < 0) return {};
  std::string text(max_bytes, '\0');
  const ssize_t got = read(fd, text.data(), text.size());
  close(fd);
  text.resize(got > 0 ? static_cast<std::size_t>(got) : 0);
  return text;
}

std::vector<std::string> stat_fields(const std::string& text) {
  std::vector<std::string> fields;
  const auto close_paren = text.rfind(')');
  if (close_paren == std::string::npos) return fields;
  std::size_t at = close_paren + 2;
  while (at < text.size()) {
    const auto end = text.find(' ', at);
    fields.push_back(text.substr(at, end == std::string::npos ? std::string::npos : end - at));
    if (end == std::string::npos) break;
    at = end + 1;
  }
  return fields;
}

double cpu_seconds(const rusage& usage) {
  const auto seconds = [](const timeval& time) {
    return static_cast<double>(time.tv_sec) + static_cast<double>(time.tv_usec) / 1e6;
  };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

}  // namespace ocp::sim_app
