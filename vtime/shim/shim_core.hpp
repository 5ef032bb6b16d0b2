#pragma once
// What the shim's files share (docs/virtual-time.md): shim.cpp holds the clock, the control
// channel and the waits on descriptors; object_waits.cpp the waits on an object (condition
// variables, semaphores, timed locks, futex words) and the waker thread; socket_reads.cpp the
// blocking reads of an OCP socket. All of it is hidden: the shim exports only what it wraps.
//
// Written against libc only: no exceptions, no allocation on the wait paths, no C++ library.
#include <dlfcn.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <time.h>

#include <atomic>
#include <cerrno>
#include <cstdint>

#include "vtime/protocol.hpp"

#pragma GCC visibility push(hidden)
namespace ocp_vtime_shim {

using ocp::vtime::ControlMessage;
using ocp::vtime::ShimKind;
using ocp::vtime::ShimMessage;
using ocp::vtime::WaitKind;
using ocp::vtime::no_deadline;

// The next definition of a wrapped function (libc's), looked up once.
template <class F>
F next_symbol(F& slot, const char* name) {
  if (slot == nullptr) slot = reinterpret_cast<F>(dlsym(RTLD_NEXT, name));
  return slot;
}
#define REAL(name) ::ocp_vtime_shim::next_symbol(real_##name, #name)

// OCP_VTIME_SOCKET was set and the clock page mapped; false again once the controller is gone.
extern std::atomic<bool> active;

// ---- the clock
std::int64_t now_us();   // virtual microseconds since the world began
timespec to_timespec(std::int64_t us);
std::int64_t micros_up(const timespec& ts);   // rounded up: a wait never ends before its time
std::int64_t after(std::int64_t relative_us); // the virtual deadline `relative_us` from now
std::int64_t absolute_deadline(clockid_t clock, const timespec& when);
bool is_cpu_clock(clockid_t clock);

// ---- this thread's control connection
bool ensure_channel(ShimKind greeting = ShimKind::hello);
int channel_fd();
std::uint64_t next_seq();      // the seq of a new BLOCKED
std::uint64_t current_seq();
void send_message(ShimMessage& message);   // fills in pid and tid
void say_running(std::uint64_t seq);       // left the wait `seq` by itself
void lost_controller();                    // the controller went away: real time from now on
void add_written(ShimMessage& message);    // the bytes written to every OCP socket
std::int64_t earliest_timer();             // of the virtual timerfds
void fire_due_timers();
void await_deliveries();
bool is_tagged(int fd);                    // an OCP socket (loopback TCP this process made)
void forget_waker_after_fork();            // object_waits.cpp
int real_ppoll_call(pollfd* fds, nfds_t count, const timespec* timeout, const sigset_t* sigmask);

// One wait on virtual time. `check` looks without blocking (>0 ready, <0 error, 0 nothing);
// `watch`/`watched` are the descriptors whose readiness also ends the kernel wait (the
// program's own, so that another thread or a delivery wakes it), `sigmask` the mask to wait
// under. Returns check's result, or 0 when the deadline came first.
inline constexpr int max_watched = 256;

// A wait whose deadline has already come, and that finds nothing: in real time the clock moves
// on between such calls, so a loop of them ends; in virtual time it would not (time stands
// still while a thread runs). A client whose float time arithmetic says "wait 0 s" while "not
// due yet" (Python's time.monotonic() at some instants) would spin for ever. So, as Shadow
// models the latency of unblocked system calls, the 64th fruitless zero-timeout wait in a row
// of one thread at one instant waits 1 µs of virtual time instead. It counts calls, not wall
// time, so it stays deterministic.
inline constexpr int fruitless_waits_before_a_tick = 64;
inline thread_local std::int64_t fruitless_instant = -1;
inline thread_local int fruitless_waits = 0;

inline bool spinning_at_one_instant() {
  const std::int64_t now = now_us();
  if (now != fruitless_instant) {
    fruitless_instant = now;
    fruitless_waits = 0;
  }
  if (++fruitless_waits < fruitless_waits_before_a_tick) return false;
  fruitless_waits = 0;
  return true;
}

template <class Check>
int virtual_wait(WaitKind kind, std::int64_t deadline, const pollfd* watch, int watched, const sigset_t* sigmask,
                 Check&& check) {
  int result = check();
  if (result != 0) return result;
  if (deadline <= now_us()) {
    if (!spinning_at_one_instant()) return 0;
    deadline = now_us() + 1;
  }
  if (!ensure_channel()) {
    active = false;   // no controller (any more): real time
    return check();
  }
  pollfd fds[max_watched + 1];
  fds[0] = {channel_fd(), POLLIN, 0};
  const int count = watched < max_watched ? watched : max_watched;
  for (int i = 0; i < count; ++i) fds[i + 1] = watch[i];
  for (;;) {
    ShimMessage blocked{};
    blocked.kind = ShimKind::blocked;
    blocked.wait = kind;
    blocked.seq = next_seq();
    const std::int64_t timer = earliest_timer();
    blocked.deadline_us = deadline < timer ? deadline : timer;
    add_written(blocked);
    send_message(blocked);
    bool answered = false;
    while (!answered) {
      for (int i = 0; i <= count; ++i) fds[i].revents = 0;
      const int woke = real_ppoll_call(fds, static_cast<nfds_t>(count + 1), nullptr, sigmask);
      if (woke < 0) {
        const int error = errno;
        say_running(blocked.seq);
        errno = error;
        return -1;
      }
      if (fds[0].revents & (POLLHUP | POLLERR)) {
        // The controller went away (the world ended): the process lives on in real time until
        // it is stopped, so that a shutdown it starts on SIGTERM can finish.
        lost_controller();
        return check();
      }
      if (fds[0].revents & POLLIN) {
        ControlMessage message{};
        while (recv(fds[0].fd, &message, sizeof message, MSG_DONTWAIT) == static_cast<ssize_t>(sizeof message)) {
          if (message.seq == blocked.seq) answered = true;
        }
      }
      fire_due_timers();
      await_deliveries();
      result = check();
      if (result != 0 || deadline <= now_us()) {
        if (!answered) say_running(blocked.seq);
        return result;
      }
    }
  }
}

}  // namespace ocp_vtime_shim
#pragma GCC visibility pop
