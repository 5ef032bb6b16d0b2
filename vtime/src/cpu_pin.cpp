// One CPU for a world (cpu_pin.hpp).
#include "cpu_pin.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cstdio>
#include <vector>

namespace ocp::vtime {

namespace {

// A lock per CPU, so that two worlds (two campaign workers, two ctest processes, two Slurm
// tasks on one node) take different CPUs. flock is per open file: it works between the
// threads of one process as between processes, and is let go when the holder dies.
int lock_cpu(int cpu) {
  char path[96];
  std::snprintf(path, sizeof path, "/tmp/ocp-vtime-%u-cpu%d.lock", static_cast<unsigned>(getuid()), cpu);
  const int fd = open(path, O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0600);
  if (fd < 0) return -1;
  if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
    close(fd);
    return -1;
  }
  return fd;
}

}  // namespace

CpuPin::CpuPin() {
  thread_ = gettid();
  if (sched_getaffinity(thread_, sizeof before_, &before_) != 0) return;
  std::vector<int> allowed;
  for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu) {
    if (CPU_ISSET(cpu, &before_)) allowed.push_back(cpu);
  }
  if (allowed.empty()) return;
  const int here = sched_getcpu();
  std::size_t start = 0;
  for (std::size_t i = 0; i < allowed.size(); ++i) {
    if (allowed[i] == here) start = i;
  }
  int chosen = allowed[start];
  for (std::size_t i = 0; i < allowed.size(); ++i) {
    const int cpu = allowed[(start + i) % allowed.size()];
    lock_fd_ = lock_cpu(cpu);
    if (lock_fd_ >= 0) {
      chosen = cpu;
      break;
    }
  }
  cpu_set_t one;
  CPU_ZERO(&one);
  CPU_SET(chosen, &one);
  if (sched_setaffinity(thread_, sizeof one, &one) != 0) return;
  restore_ = true;
  cpu_ = chosen;
  // SCHED_BATCH: a woken batch thread does not preempt the one running. So the controller,
  // woken by a client's BLOCKED, lets the client reach its wait; and a client (it inherits the
  // policy) woken by the simulator's bytes lets the controller finish the instant. Each runs
  // until it waits, and the CPU changes hands once per hand-off.
  if (sched_getscheduler(thread_) == SCHED_OTHER) {
    const sched_param none{};
    batch_ = sched_setscheduler(thread_, SCHED_BATCH, &none) == 0;
  }
}

CpuPin::~CpuPin() {
  if (batch_) {
    const sched_param none{};
    (void)sched_setscheduler(thread_, SCHED_OTHER, &none);
  }
  if (restore_) (void)sched_setaffinity(thread_, sizeof before_, &before_);
  if (lock_fd_ >= 0) close(lock_fd_);
}

bool CpuPin::holds(pid_t tid) const {
  if (cpu_ < 0) return false;
  cpu_set_t mask;
  if (sched_getaffinity(tid, sizeof mask, &mask) != 0) return false;
  return CPU_COUNT(&mask) == 1 && CPU_ISSET(cpu_, &mask);
}

}  // namespace ocp::vtime
