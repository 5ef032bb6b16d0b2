#pragma once
// Each thread's share of a fleet point: CPU, time spent runnable but waiting for a core, and
// context switches, per thread of this process, between two snapshots. The process total
// (getrusage) says how much the point costs; this says where, so a saturated thread (one near
// 1 CPU s per wall s, or one that waits long for a core) shows by name. Threads are named with
// pthread_setname_np where the point starts them ("player", "streamers-0", "clients-0" …).
//
// Read from /proc/self/task/<tid>/ and each thread's CPU clock: the CPU from the clock (falling
// back to schedstat's ns, then to stat's utime + stime in clock ticks), the run-queue wait from
// schedstat, the voluntary and involuntary context switches from status.
#include <cstdint>
#include <vector>

namespace ocp::bench {

struct ThreadSample {
  int tid = 0;
  char name[16] = {};   // the kernel's comm: at most 15 characters
  double cpu_s = 0;
  double wait_s = 0;    // runnable, waiting for a core (0 without schedstat)
  std::uint64_t voluntary_switches = 0;     // went to sleep (epoll, a lock): roughly wake-ups
  std::uint64_t involuntary_switches = 0;   // pre-empted
};

// Every thread of this process now, in thread id order.
std::vector<ThreadSample> sample_threads();

// What each thread of `after` used since `before` (a thread new since then counts from zero);
// threads that ended in between, and those that did nothing in between, are not in it.
std::vector<ThreadSample> thread_usage_between(const std::vector<ThreadSample>& before,
                                               const std::vector<ThreadSample>& after);

// Names the calling thread (truncated to 15 characters, as the kernel keeps them).
void name_this_thread(const char* name);

// Names the calling thread for a scope, then gives it its old name back (the main thread
// hosts the Player during a point, and `--in-process` runs several points on it).
class ScopedThreadName {
 public:
  explicit ScopedThreadName(const char* name);
  ~ScopedThreadName();
  ScopedThreadName(const ScopedThreadName&) = delete;
  ScopedThreadName& operator=(const ScopedThreadName&) = delete;

 private:
  char old_[16] = {};
};

}  // namespace ocp::bench
