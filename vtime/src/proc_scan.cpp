// /proc looks at a client's threads (proc_scan.hpp).
#include "proc_scan.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>

#include "sim_app/proc_stat.hpp"

namespace ocp::vtime {

namespace {

// The state (field 3 of stat) and the CPU it last ran on (field 39), without splitting the
// whole line: a look reads it for every thread at every quiescence wait.
bool read_state_and_cpu(const std::string& text, ThreadLook& look) {
  const auto close_paren = text.rfind(')');
  if (close_paren == std::string::npos || close_paren + 2 >= text.size()) return false;
  look.state = text[close_paren + 2];
  std::size_t at = close_paren + 2;
  for (int field = 3; field < 39 && at != std::string::npos; ++field) {
    at = text.find(' ', at);
    if (at != std::string::npos) ++at;
  }
  if (at != std::string::npos && at < text.size()) look.cpu = std::atoi(text.c_str() + at);
  return true;
}

}  // namespace

ProcScanner::~ProcScanner() {
  for (auto& [pid, files] : processes_) {
    for (auto& [tid, task] : files.task) close_task(task);
    if (files.tasks != nullptr) closedir(files.tasks);
  }
}

void ProcScanner::close_task(TaskFiles& files) {
  for (int* fd : {&files.stat, &files.schedstat, &files.children}) {
    if (*fd < 0) continue;
    close(*fd);
    *fd = -1;
    --open_;
  }
}

void ProcScanner::forget(pid_t pid) {
  const auto found = processes_.find(pid);
  if (found == processes_.end()) return;
  for (auto& [tid, task] : found->second.task) close_task(task);
  if (found->second.tasks != nullptr) closedir(found->second.tasks);
  processes_.erase(found);
}

ProcScanner::ProcessFiles* ProcScanner::process(pid_t pid) {
  ProcessFiles& files = processes_[pid];
  if (files.tasks != nullptr) return &files;
  char path[64];
  std::snprintf(path, sizeof path, "/proc/%d/task", static_cast<int>(pid));
  files.tasks = opendir(path);
  if (files.tasks == nullptr) {
    processes_.erase(pid);
    return nullptr;
  }
  return &files;
}

std::vector<pid_t> ProcScanner::task_ids(pid_t pid) {
  if (const auto listed = listed_.find(pid); caching_ && listed != listed_.end()) return listed->second;
  std::vector<pid_t> tids;
  ProcessFiles* files = process(pid);
  if (files == nullptr) return tids;
  rewinddir(files->tasks);   // the directory is read afresh
  while (const dirent* entry = readdir(files->tasks)) {
    if (entry->d_name[0] >= '0' && entry->d_name[0] <= '9') tids.push_back(static_cast<pid_t>(std::atoi(entry->d_name)));
  }
  if (tids.empty()) {
    forget(pid);   // gone (an ended process's directory lists nothing)
    return tids;
  }
  std::sort(tids.begin(), tids.end());
  // Threads that ended: their files go.
  for (auto it = files->task.begin(); it != files->task.end();) {
    if (std::binary_search(tids.begin(), tids.end(), it->first)) {
      ++it;
    } else {
      close_task(it->second);
      it = files->task.erase(it);
    }
  }
  if (caching_) listed_[pid] = tids;
  return tids;
}

std::string ProcScanner::read_task_file(pid_t pid, pid_t tid, const char* name, int& fd) {
  char path[96];
  std::snprintf(path, sizeof path, "/proc/%d/task/%d/%s", static_cast<int>(pid), static_cast<int>(tid), name);
  if (fd < 0 && open_ < max_open_) {
    fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd >= 0) ++open_;
  }
  if (fd < 0) return sim_app::read_small_proc_file(path);
  char buffer[1024];
  const ssize_t got = pread(fd, buffer, sizeof buffer - 1, 0);
  return got > 0 ? std::string(buffer, static_cast<std::size_t>(got)) : std::string();
}

std::vector<ThreadLook> ProcScanner::look_at_threads(pid_t pid, bool runs) {
  std::vector<ThreadLook> threads;
  for (const pid_t tid : task_ids(pid)) {
    TaskFiles& files = processes_[pid].task[tid];
    ThreadLook look;
    look.tid = tid;
    const std::string stat = read_task_file(pid, tid, "stat", files.stat);
    if (!read_state_and_cpu(stat, look)) continue;   // ended meanwhile
    if (!runs) {
      threads.push_back(look);
      continue;
    }
    const std::string schedstat = read_task_file(pid, tid, "schedstat", files.schedstat);
    const auto last_space = schedstat.rfind(' ');
    look.runs = last_space == std::string::npos ? 0 : std::strtoull(schedstat.c_str() + last_space + 1, nullptr, 10);
    threads.push_back(look);
  }
  return threads;
}

bool asleep_in_both(const std::vector<ThreadLook>& first, const std::vector<ThreadLook>& second) {
  if (first.size() != second.size()) return false;
  for (std::size_t i = 0; i < first.size(); ++i) {
    const bool gone = first[i].state == 'Z' || first[i].state == 'X';
    if (first[i].tid != second[i].tid) return false;
    if (gone && (second[i].state == 'Z' || second[i].state == 'X')) continue;
    if (first[i].state != 'S' || second[i].state != 'S' || first[i].runs != second[i].runs) return false;
  }
  return true;
}

std::vector<pid_t> ProcScanner::process_tree(pid_t root, std::size_t limit) {
  std::vector<pid_t> tree{root};
  for (std::size_t next = 0; next < tree.size() && tree.size() < limit; ++next) {
    const pid_t pid = tree[next];
    for (const pid_t tid : task_ids(pid)) {
      const std::string text = read_task_file(pid, tid, "children", processes_[pid].task[tid].children);
      const char* at = text.c_str();
      char* end = nullptr;
      for (long child = std::strtol(at, &end, 10); end != at && tree.size() < limit; child = std::strtol(at, &end, 10)) {
        tree.push_back(static_cast<pid_t>(child));
        at = end;
      }
    }
  }
  return tree;
}

std::uint64_t cpu_ticks(pid_t pid) {
  char path[64];
  std::snprintf(path, sizeof path, "/proc/%d/stat", static_cast<int>(pid));
  const std::vector<std::string> fields = sim_app::stat_fields(sim_app::read_small_proc_file(path));
  // utime and stime are fields 14 and 15 of stat; here, after pid and comm, 11 and 12.
  if (fields.size() < 13) return 0;
  return std::strtoull(fields[11].c_str(), nullptr, 10) + std::strtoull(fields[12].c_str(), nullptr, 10);
}

std::string describe_awake(const std::vector<ThreadLook>& look) {
  std::string out;
  for (const ThreadLook& thread : look) {
    if (thread.state == 'S' || thread.state == 'Z' || thread.state == 'X') continue;
    if (!out.empty()) out += ", ";
    out += "thread " + std::to_string(thread.tid) + " in state " + thread.state;
  }
  return out;
}

}  // namespace ocp::vtime
