#pragma once
// Whether a process's threads are all asleep and stayed so (docs/virtual-time.md, quiescence):
// the waits the shim does not wrap (a mutex, a blocking read) are confirmed idle here, from
// /proc/PID/task/*/stat (the state) and /proc/PID/task/*/schedstat (how often each ran).
#include <sys/types.h>

#include <cstdint>
#include <string>
#include <vector>

namespace ocp::vtime {

struct ThreadLook {
  pid_t tid = 0;
  char state = '?';
  std::uint64_t runs = 0;   // times scheduled in
};

// Every thread of `pid` now; empty when the process is gone.
std::vector<ThreadLook> look_at_threads(pid_t pid);
// All asleep (S), and the same threads with the same run counts in both looks.
bool asleep_in_both(const std::vector<ThreadLook>& first, const std::vector<ThreadLook>& second);
// `pid` and every process below it (/proc/PID/task/*/children), at most `limit`.
std::vector<pid_t> process_tree(pid_t pid, std::size_t limit);
// The process's CPU time (user + system), in clock ticks; 0 when gone.
std::uint64_t cpu_ticks(pid_t pid);
// "S (sleeping)" style summary of the threads not asleep, for messages.
std::string describe_awake(const std::vector<ThreadLook>& look);

}  // namespace ocp::vtime
