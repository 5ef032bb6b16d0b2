#pragma once
// The wire between the virtual-time shim (vtime/shim, preloaded into a client process) and its
// controller (vtime/src/controller.cpp, in the simulator). Shared by both sides, so it holds
// only fixed-size, trivially copyable types and no library.
//
//   * The clock page: a small shared file the controller writes and every shim maps read-only.
//     It holds the virtual time (microseconds since the world began) and, per OCP connection,
//     how many bytes the controller has written to it, so a woken thread can wait until they
//     have arrived before it looks at its sockets.
//   * The control socket: one SOCK_SEQPACKET connection per client thread. A thread says HELLO
//     once, CONNECTED after it connects to loopback TCP, BLOCKED(seq, deadline) when it waits,
//     RUNNING(seq) when it left a wait the controller did not end, and CLOSED when it closes an
//     OCP socket. The controller answers a BLOCKED with WAKE(seq) (deadline reached) or
//     POKE(seq) (something was delivered: look again).
//   * Waits on an object (a condition variable, a futex word: timed cond waits, sem_timedwait,
//     timed locks and reader-writer locks, syscall(SYS_futex)) sleep in the kernel on the object itself, not on the
//     control socket, so their WAKE goes to the process's *waker*: a thread the shim starts on
//     the first such wait, with its own connection (WAKER_HELLO), always asleep in recv. It
//     wakes the object for real (a broadcast, a FUTEX_WAKE); the waiter sees its deadline passed.
#include <atomic>
#include <cstdint>

namespace ocp::vtime {

inline constexpr const char* socket_env = "OCP_VTIME_SOCKET";   // the control socket's path
inline constexpr const char* clock_env = "OCP_VTIME_CLOCK";     // the clock page's path

inline constexpr std::int64_t no_deadline = INT64_MAX;
// What the virtual clocks read at virtual time 0: MONOTONIC (and BOOTTIME, RAW, COARSE) start
// at 10^9 s (31.7 years), REALTIME at 2026-01-01T00:00:00Z. The monotonic origin is far beyond
// any machine's uptime so that a virtual deadline reaching the kernel in a timed wait the shim
// does not see (made inside libc) is a far-future wait there, not an instant timeout (a busy
// loop); the thread then sleeps until it is woken for real. In nanoseconds it is 10^18, well
// inside an int64.
inline constexpr std::int64_t monotonic_origin_us = 1'000'000'000'000'000;
inline constexpr std::int64_t realtime_origin_us = 1'767'225'600'000'000;

inline constexpr int max_connections = 16;   // OCP sockets per clock page / per process

struct DeliveredCount {
  std::atomic<std::uint32_t> port;        // the client's local port (0: unused)
  std::atomic<std::uint64_t> delivered;   // bytes the controller wrote to it so far
};

struct ClockPage {
  std::atomic<std::int64_t> now_us;
  std::atomic<std::uint32_t> connections;
  std::uint32_t reserved;
  DeliveredCount delivered[max_connections];
};
static_assert(std::atomic<std::int64_t>::is_always_lock_free && std::atomic<std::uint64_t>::is_always_lock_free);

enum class ShimKind : std::uint32_t { hello = 1, blocked = 2, running = 3, connected = 4, closed = 5, waker_hello = 6 };
// futex, cond, lock, semaphore and rwlock waits sleep on an object (`object`): their WAKE goes to the waker.
enum class WaitKind : std::uint32_t {
  none = 0, sleep = 1, poll = 2, select = 3, epoll = 4, futex = 5, cond = 6, lock = 7, semaphore = 8, read = 9,
  rwlock = 10
};
inline constexpr bool waits_on_object(WaitKind kind) {
  return kind == WaitKind::futex || kind == WaitKind::cond || kind == WaitKind::lock || kind == WaitKind::semaphore ||
         kind == WaitKind::rwlock;
}
// For the wait trace: "waits in <name>".
inline constexpr const char* wait_name(WaitKind kind) {
  switch (kind) {
    case WaitKind::sleep: return "sleep";
    case WaitKind::poll: return "poll";
    case WaitKind::select: return "select";
    case WaitKind::epoll: return "epoll_wait";
    case WaitKind::futex: return "a futex wait";
    case WaitKind::cond: return "a timed condition wait";
    case WaitKind::lock: return "a timed lock";
    case WaitKind::rwlock: return "a timed reader-writer lock";
    case WaitKind::semaphore: return "sem_timedwait";
    case WaitKind::read: return "a blocking read";
    case WaitKind::none: break;
  }
  return "wait";
}

// Per OCP connection, with every BLOCKED: what the controller needs to take the client's bytes
// and to model its kernel's Nagle algorithm (docs/virtual-time.md, "Nagle's algorithm").
struct WrittenCount {
  std::uint32_t port;
  std::uint32_t no_delay;          // 1: the program set TCP_NODELAY (the real socket always has it)
  std::uint64_t written;           // bytes the process wrote to that socket so far
  std::uint64_t first_write_end;   // `written` after the first write since the last report; 0: none
};

inline constexpr int max_reported = 8;

// A wait on an object (a condition variable, a lock, a semaphore, a futex word), as a BLOCKED
// describes it and as a wake through the process's waker names it back.
struct ObjectWait {
  std::uint32_t slot;         // the waiter's slot in its process
  std::uint32_t futex_flags;  // on a futex word: FUTEX_PRIVATE_FLAG or 0
  std::uint64_t object;       // its address in the client
};

struct ShimMessage {
  ShimKind kind;
  WaitKind wait;
  std::int32_t pid;
  std::int32_t tid;
  std::uint64_t seq;
  std::int64_t deadline_us;   // virtual; no_deadline when none
  std::uint32_t port;         // connected / closed: the client's local port
  std::uint32_t remote_port;  // connected: the port it connected to
  std::uint32_t reported;     // entries used in `written`
  std::uint32_t reserved;
  ObjectWait on_object;       // blocked on an object
  WrittenCount written[max_reported];
};

enum class ControlKind : std::uint32_t { wake = 1, poke = 2 };

struct ControlMessage {
  ControlKind kind;
  std::uint32_t reserved;
  std::uint64_t seq;   // the BLOCKED it answers
  // To a waker: the waiter's wait, as its BLOCKED described it.
  WaitKind wait;
  std::int32_t tid;
  ObjectWait on_object;
};

}  // namespace ocp::vtime
