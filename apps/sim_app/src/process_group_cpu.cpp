#include "process_group_cpu.hpp"

#include <dirent.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "sim_app/proc_stat.hpp"

namespace ocp::sim_app {
namespace {

// A stat line is well under 1 KiB; the fields read here (up to 17) come within its first few
// hundred bytes.
constexpr std::size_t stat_max_bytes = 2047;

struct GroupAndTicks {
  long group = -1;
  unsigned long long ticks = 0;   // utime + stime + cutime + cstime
};

bool read_stat(const char* pid, GroupAndTicks& out) {
  char path[64];
  std::snprintf(path, sizeof path, "/proc/%s/stat", pid);
  // Empty when the process ended meanwhile.
  const std::vector<std::string> fields = stat_fields(read_small_proc_file(path, stat_max_bytes));
  // fields[0] is the state (field 3), then ppid, pgrp (5), …, utime (14), stime, cutime, cstime (17).
  if (fields.size() < 15) return false;
  unsigned long long numbers[15] = {};
  for (std::size_t index = 1; index < 15; ++index) {
    char* end = nullptr;
    numbers[index] = std::strtoull(fields[index].c_str(), &end, 10);
    if (end == fields[index].c_str()) return false;
  }
  out.group = static_cast<long>(numbers[2]);
  out.ticks = numbers[11] + numbers[12] + numbers[13] + numbers[14];
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
