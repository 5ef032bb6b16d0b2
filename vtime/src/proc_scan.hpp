#pragma once
// Whether a process's threads are all asleep and stayed so (docs/virtual-time.md, quiescence):
// the waits the shim does not wrap (a mutex, a blocking read) are confirmed idle here, from
// /proc/PID/task/*/stat (the state) and /proc/PID/task/*/schedstat (how often each ran).
#include <sys/types.h>

#include <dirent.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace ocp::vtime {

struct ThreadLook {
  pid_t tid = 0;
  char state = '?';
  std::uint64_t runs = 0;   // times scheduled in (0 when not asked for)
  int cpu = -1;             // the CPU it last ran on
};

// The looks, with the /proc files kept open between them and read again with pread: a
// quiescence wait looks at every thread twice per virtual instant, and opening the files each
// time was most of the controller's CPU (docs/benchmarks.md, "External clients in virtual
// time"). A descriptor names one task for good: a thread that ended reads as gone, and a
// reused thread id gets fresh files. At most `max_open` descriptors; beyond, files are opened
// for each read.
class ProcScanner {
 public:
  explicit ProcScanner(std::size_t max_open = 768) : max_open_(max_open) {}
  ~ProcScanner();
  ProcScanner(const ProcScanner&) = delete;
  ProcScanner& operator=(const ProcScanner&) = delete;

  // Every thread of `pid` now; empty when the process is gone. Without `runs`, only each
  // thread's stat file is read.
  std::vector<ThreadLook> look_at_threads(pid_t pid, bool runs = true);
  // `pid` and every process below it (/proc/PID/task/*/children), at most `limit`.
  std::vector<pid_t> process_tree(pid_t pid, std::size_t limit);
  // While a OneListing lives, each process's /proc/PID/task is listed once, for its tree and
  // for its threads alike (one look at every thread; outside, every call lists afresh).
  class OneListing {
   public:
    explicit OneListing(ProcScanner& scanner) : scanner_(scanner) { scanner_.caching_ = true; }
    ~OneListing() {
      scanner_.caching_ = false;
      scanner_.listed_.clear();
    }
    OneListing(const OneListing&) = delete;
    OneListing& operator=(const OneListing&) = delete;

   private:
    ProcScanner& scanner_;
  };

 private:
  struct TaskFiles {
    int stat = -1;
    int schedstat = -1;
    int children = -1;
  };
  struct ProcessFiles {
    DIR* tasks = nullptr;
    std::map<pid_t, TaskFiles> task;
  };
  ProcessFiles* process(pid_t pid);
  std::vector<pid_t> task_ids(pid_t pid);
  // The file's text now ("" when the task is gone); `fd` is opened on first use when allowed.
  std::string read_task_file(pid_t pid, pid_t tid, const char* name, int& fd);
  void close_task(TaskFiles& files);
  void forget(pid_t pid);

  std::map<pid_t, ProcessFiles> processes_;
  std::map<pid_t, std::vector<pid_t>> listed_;   // this look's thread lists (OneListing)
  bool caching_ = false;
  std::size_t open_ = 0;
  std::size_t max_open_;
};

// All asleep (S), and the same threads with the same run counts in both looks.
bool asleep_in_both(const std::vector<ThreadLook>& first, const std::vector<ThreadLook>& second);
// The process's CPU time (user + system), in clock ticks; 0 when gone.
std::uint64_t cpu_ticks(pid_t pid);
// "S (sleeping)" style summary of the threads not asleep, for messages.
std::string describe_awake(const std::vector<ThreadLook>& look);

}  // namespace ocp::vtime
