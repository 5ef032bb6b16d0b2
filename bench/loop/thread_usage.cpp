#include "thread_usage.hpp"

#include <dirent.h>
#include <pthread.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "sim_app/proc_stat.hpp"

namespace ocp::bench {

namespace {

// At most 4 KiB of one small /proc file (status is the largest read here); empty if it cannot
// be read.
std::string read_small_file(const std::string& path) { return sim_app::read_small_proc_file(path.c_str(), 4095); }

// stat: "tid (comm) state …"; comm may hold spaces and parentheses, so it ends at the last ')'.
// Fills the name and, from fields 14 and 15 (utime, stime), the CPU; false if malformed.
bool read_stat(const std::string& directory, ThreadSample& sample) {
  const std::string stat = read_small_file(directory + "/stat");
  const std::size_t open = stat.find('(');
  const std::size_t close = stat.rfind(')');
  if (open == std::string::npos || close == std::string::npos || close < open) return false;
  const std::string comm = stat.substr(open + 1, std::min<std::size_t>(close - open - 1, sizeof sample.name - 1));
  std::memcpy(sample.name, comm.c_str(), comm.size() + 1);
  unsigned long utime = 0, stime = 0;
  // After ") ": state (field 3) … utime is field 14, stime 15.
  if (std::sscanf(stat.c_str() + close + 1, " %*c %*d %*d %*d %*d %*d %*u %*u %*u %*u %*u %lu %lu", &utime, &stime) != 2) {
    return false;
  }
  sample.cpu_s = static_cast<double>(utime + stime) / static_cast<double>(sysconf(_SC_CLK_TCK));
  return true;
}

// schedstat: "ns on CPU, ns waiting on a run queue, time slices"; absent without CONFIG_SCHED_INFO.
// Its CPU figure lags a running thread's by up to a scheduler tick, so the CPU comes from the
// thread's CPU clock where the kernel gives one (cpu_clock_seconds).
void read_schedstat(const std::string& directory, ThreadSample& sample) {
  unsigned long long run_ns = 0, wait_ns = 0;
  if (std::sscanf(read_small_file(directory + "/schedstat").c_str(), "%llu %llu", &run_ns, &wait_ns) == 2) {
    sample.cpu_s = static_cast<double>(run_ns) / 1e9;
    sample.wait_s = static_cast<double>(wait_ns) / 1e9;
  }
}

// The CPU clock of thread `tid` of this process, exact to the nanosecond for a running thread
// too: the kernel's clock id for a thread's scheduler clock (what pthread_getcpuclockid makes
// from a pthread_t, built here from the thread id the /proc listing gives). Negative if none.
double cpu_clock_seconds(int tid) {
  const clockid_t clock = static_cast<clockid_t>((~static_cast<unsigned>(tid) << 3) | 6U);   // per-thread, sched
  timespec now{};
  if (clock_gettime(clock, &now) != 0) return -1.0;
  return static_cast<double>(now.tv_sec) + static_cast<double>(now.tv_nsec) / 1e9;
}

std::uint64_t status_field(const std::string& status, const char* key) {
  const std::size_t at = status.find(key);
  return at == std::string::npos ? 0 : std::strtoull(status.c_str() + at + std::strlen(key), nullptr, 10);
}

}  // namespace

std::vector<ThreadSample> sample_threads() {
  std::vector<ThreadSample> samples;
  DIR* tasks = opendir("/proc/self/task");
  if (tasks == nullptr) return samples;
  while (const dirent* entry = readdir(tasks)) {
    const int tid = std::atoi(entry->d_name);
    if (tid <= 0) continue;
    const std::string directory = std::string("/proc/self/task/") + entry->d_name;
    ThreadSample sample;
    sample.tid = tid;
    if (!read_stat(directory, sample)) continue;   // ended while being read
    read_schedstat(directory, sample);
    if (const double cpu_s = cpu_clock_seconds(tid); cpu_s >= 0) sample.cpu_s = cpu_s;
    const std::string status = read_small_file(directory + "/status");
    sample.voluntary_switches = status_field(status, "\nvoluntary_ctxt_switches:");
    sample.involuntary_switches = status_field(status, "\nnonvoluntary_ctxt_switches:");
    samples.push_back(sample);
  }
  closedir(tasks);
  std::sort(samples.begin(), samples.end(), [](const auto& a, const auto& b) { return a.tid < b.tid; });
  return samples;
}

std::vector<ThreadSample> thread_usage_between(const std::vector<ThreadSample>& before,
                                               const std::vector<ThreadSample>& after) {
  std::vector<ThreadSample> used;
  for (ThreadSample sample : after) {
    const auto earlier = std::find_if(before.begin(), before.end(), [&](const auto& b) { return b.tid == sample.tid; });
    if (earlier != before.end()) {
      sample.cpu_s -= earlier->cpu_s;
      sample.wait_s -= earlier->wait_s;
      sample.voluntary_switches -= std::min(sample.voluntary_switches, earlier->voluntary_switches);
      sample.involuntary_switches -= std::min(sample.involuntary_switches, earlier->involuntary_switches);
    }
    // A thread that neither ran nor slept in between (an idle resolver thread of Asio's) says nothing.
    if (sample.cpu_s > 0 || sample.voluntary_switches > 0) used.push_back(sample);
  }
  return used;
}

void name_this_thread(const char* name) {
  char truncated[16] = {};
  std::memcpy(truncated, name, std::min(std::strlen(name), sizeof truncated - 1));
  pthread_setname_np(pthread_self(), truncated);
}

ScopedThreadName::ScopedThreadName(const char* name) {
  pthread_getname_np(pthread_self(), old_, sizeof old_);
  name_this_thread(name);
}

ScopedThreadName::~ScopedThreadName() { name_this_thread(old_); }

}  // namespace ocp::bench
