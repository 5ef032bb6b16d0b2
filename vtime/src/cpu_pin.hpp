#pragma once
// One CPU for a world's controller and its client processes (docs/virtual-time.md, "Speed").
//
// Virtual time is a ping-pong: the controller wakes a client thread, the client runs and
// blocks, the controller wakes again. When the two sleep on different CPUs, every hand-off
// wakes an idle CPU, and on a virtual machine an idle vCPU is halted: waking it costs an exit
// to the host, tens of microseconds. Pinned to one CPU, a hand-off is a context switch.
// Measured on this project's 2-core VM, idle: the reference client 35× → 65× real time, the
// Python example 32× → 52× (docs/benchmarks.md).
//
// The pin also makes one /proc look enough (controller.cpp, single_look): while the pinned
// controller runs without being switched out, no thread pinned to its CPU can run.
#include <sched.h>
#include <sys/types.h>

namespace ocp::vtime {

class CpuPin {
 public:
  // Pins the calling thread (and so every process it launches from now on) to one CPU of the
  // ones it may use: the first whose lock no other pin of this user on this machine holds,
  // starting from the CPU the thread is on. With every CPU taken, it shares the current one.
  CpuPin();
  ~CpuPin();   // the thread's CPUs as they were
  CpuPin(const CpuPin&) = delete;
  CpuPin& operator=(const CpuPin&) = delete;

  // The CPU, or -1 when the thread could not be pinned.
  int cpu() const { return cpu_; }
  // Whether thread `tid` may run on the pinned CPU only.
  bool holds(pid_t tid) const;

 private:
  cpu_set_t before_{};
  pid_t thread_ = 0;   // the pinned thread: restored even when another thread ends the pin
  bool restore_ = false;
  int cpu_ = -1;
  int lock_fd_ = -1;
  bool batch_ = false;   // SCHED_BATCH set here
};

}  // namespace ocp::vtime
