#include "process_group_cpu.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <unistd.h>

#include <array>
#include <cstdlib>
#include <cstring>
#include <memory>

namespace ocp::sim_app {
namespace {

// A stat line is well under 1 KiB; the comm field (in parentheses, any bytes) comes first, so
// the fields are counted from its closing parenthesis.
constexpr std::size_t stat_limit = 2048;

struct GroupAndTicks {
  long group = -1;
  unsigned long long ticks = 0;   // utime + stime + cutime + cstime
};

bool read_stat(const char* pid, GroupAndTicks& out) {
  char path[64];
  std::snprintf(path, sizeof path, "/proc/%s/stat", pid);
  const int fd = open(path, O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;   // ended meanwhile
  std::array<char, stat_limit> text{};
  const ssize_t got = read(fd, text.data(), text.size() - 1);
  close(fd);
  if (got <= 0) return false;
  const char* close_paren = std::strrchr(text.data(), ')');
  if (close_paren == nullptr) return false;
  // After ") ": state (field 3), ppid, pgrp (5), …, utime (14), stime, cutime, cstime (17).
  const char* cursor = close_paren + 1;
  unsigned long long fields[15] = {};
  for (int index = 0; index < 15; ++index) {
    while (*cursor == ' ') ++cursor;
    if (*cursor == '\0') return false;
    if (index == 0) {
      ++cursor;   // the state letter
    } else {
      char* end = nullptr;
      fields[index] = std::strtoull(cursor, &end, 10);
      if (end == cursor) return false;
      cursor = end;
    }
  }
  out.group = static_cast<long>(fields[2]);
  out.ticks = fields[11] + fields[12] + fields[13] + fields[14];
  return true;
}

}  // namespace

double process_group_cpu_seconds(pid_t group) {
  const std::unique_ptr<DIR, int (*)(DIR*)> proc(opendir("/proc"), closedir);
  if (!proc) return 0;
  unsigned long long ticks = 0;
  while (const dirent* entry = readdir(proc.get())) {
    if (entry->d_name[0] < '1' || entry->d_name[0] > '9') continue;   // not a process
    GroupAndTicks stat;
    if (read_stat(entry->d_name, stat) && stat.group == static_cast<long>(group)) ticks += stat.ticks;
  }
  const long per_second = sysconf(_SC_CLK_TCK);
  return per_second > 0 ? static_cast<double>(ticks) / static_cast<double>(per_second) : 0;
}

}  // namespace ocp::sim_app
