// The virtual-time shim (docs/virtual-time.md): preloaded into a client process
// (LD_PRELOAD), it puts the process on the simulator's clock. Time reads come from the clock
// page; every wait it wraps first looks (without blocking) whether the wait is already over,
// and otherwise tells the controller "blocked until this virtual deadline" and waits, in the
// kernel, for the controller's answer or for its own file descriptors. Without
// OCP_VTIME_SOCKET in the environment it does nothing: every call goes straight to libc.
//
// Written against libc only: no exceptions, no allocation on the wait paths, no C++ library.
// The waits on an object (condition variables, semaphores, timed locks, futex words) are in
// object_waits.cpp, the blocking reads of an OCP socket in socket_reads.cpp.
#include <dlfcn.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <linux/tcp.h>   // the kernel's tcp_info (tcpi_bytes_received), not glibc's older copy
#include <poll.h>
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <sys/epoll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/time.h>
#include <sys/timerfd.h>
#include <sys/uio.h>
#include <sys/un.h>
#include <time.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <climits>
#include <cstdarg>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "shim_core.hpp"
#include "vtime/protocol.hpp"

using ocp::vtime::ClockPage;
using ocp::vtime::ControlKind;
using ocp::vtime::ControlMessage;
using ocp::vtime::ShimKind;
using ocp::vtime::ShimMessage;
using ocp::vtime::WaitKind;
using ocp::vtime::no_deadline;

namespace ocp_vtime_shim __attribute__((visibility("hidden"))) {

// ---------------------------------------------------------------- the real functions

int (*real_clock_gettime)(clockid_t, timespec*);
int (*real_gettimeofday)(timeval*, void*);
time_t (*real_time)(time_t*);
int (*real_nanosleep)(const timespec*, timespec*);
int (*real_clock_nanosleep)(clockid_t, int, const timespec*, timespec*);
int (*real_usleep)(useconds_t);
unsigned (*real_sleep)(unsigned);
int (*real_poll)(pollfd*, nfds_t, int);
int (*real_ppoll)(pollfd*, nfds_t, const timespec*, const sigset_t*);
int (*real_select)(int, fd_set*, fd_set*, fd_set*, timeval*);
int (*real_pselect)(int, fd_set*, fd_set*, fd_set*, const timespec*, const sigset_t*);
int (*real_epoll_wait)(int, epoll_event*, int, int);
int (*real_epoll_pwait)(int, epoll_event*, int, int, const sigset_t*);
int (*real_timerfd_create)(int, int);
int (*real_timerfd_settime)(int, int, const itimerspec*, itimerspec*);
int (*real_timerfd_gettime)(int, itimerspec*);
int (*real_connect)(int, const sockaddr*, socklen_t);
int (*real_close)(int);
ssize_t (*real_write)(int, const void*, size_t);
ssize_t (*real_writev)(int, const iovec*, int);
ssize_t (*real_send)(int, const void*, size_t, int);
ssize_t (*real_sendto)(int, const void*, size_t, int, const sockaddr*, socklen_t);
ssize_t (*real_sendmsg)(int, const msghdr*, int);
int (*real_setsockopt)(int, int, int, const void*, socklen_t);
int (*real_getsockopt)(int, int, int, void*, socklen_t*);

// ---------------------------------------------------------------- process state

std::atomic<bool> active{false};                    // OCP_VTIME_SOCKET was set and the clock page mapped
const ClockPage* page = nullptr;
char socket_path[108] = {};

std::int64_t now_us() { return page->now_us.load(std::memory_order_acquire); }

// OCP sockets: loopback TCP connections this process made, and the bytes it wrote to each.
// The controller models the kernel's Nagle algorithm in virtual time (docs/virtual-time.md), so
// the real socket always has TCP_NODELAY (its bytes arrive at once, whatever the machine's
// load); the program's own setting is kept here and reported, with where its first write since
// the last report ended (the one write Nagle lets go at once when nothing is in flight).
struct Tagged {
  std::atomic<int> fd{-1};
  std::atomic<std::uint32_t> port{0};
  std::atomic<std::uint64_t> written{0};
  std::atomic<std::uint64_t> first_write_end{0};
  std::atomic<bool> no_delay{false};
};
Tagged tagged[ocp::vtime::max_connections];
std::atomic<int> tagged_count{0};

Tagged* find_tagged(int fd) {
  if (tagged_count.load(std::memory_order_relaxed) == 0 || fd < 0) return nullptr;
  for (Tagged& entry : tagged) {
    if (entry.fd.load(std::memory_order_relaxed) == fd) return &entry;
  }
  return nullptr;
}

// Virtual timerfds, by descriptor: the real timerfd is never armed by the program; the shim
// makes it fire (arms it for 1 ns) when virtual time reaches the deadline.
constexpr int max_timer_fds = 1024;
struct VirtualTimer {
  bool used = false;
  clockid_t clock = CLOCK_MONOTONIC;
  std::int64_t deadline_us = no_deadline;
  std::int64_t interval_us = 0;
  bool fired = false;   // made readable since it was last set: expirations may be unread
};
VirtualTimer timers[max_timer_fds];
int timers_used = 0;
int timers_end = 0;     // past the highest descriptor used
pthread_mutex_t timers_lock = PTHREAD_MUTEX_INITIALIZER;

// ---------------------------------------------------------------- conversions

bool is_cpu_clock(clockid_t clock) {
  return clock == CLOCK_PROCESS_CPUTIME_ID || clock == CLOCK_THREAD_CPUTIME_ID || clock < 0;
}
bool is_wall_clock(clockid_t clock) {
  return clock == CLOCK_REALTIME || clock == CLOCK_REALTIME_COARSE || clock == CLOCK_TAI || clock == CLOCK_REALTIME_ALARM;
}
std::int64_t origin_of(clockid_t clock) {
  return is_wall_clock(clock) ? ocp::vtime::realtime_origin_us : ocp::vtime::monotonic_origin_us;
}
timespec to_timespec(std::int64_t us) { return timespec{static_cast<time_t>(us / 1'000'000), static_cast<long>(us % 1'000'000) * 1000}; }
// Rounded up: a wait never ends before its time.
std::int64_t micros_up(const timespec& ts) {
  if (ts.tv_sec < 0) return 0;
  if (ts.tv_sec > INT64_MAX / 2'000'000) return no_deadline / 2;
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000 + (ts.tv_nsec + 999) / 1000;
}
std::int64_t after(std::int64_t relative_us) {
  const std::int64_t now = now_us();
  return relative_us >= no_deadline / 2 ? no_deadline : now + relative_us;
}
std::int64_t deadline_of_ms(int timeout_ms) { return timeout_ms < 0 ? no_deadline : after(std::int64_t{timeout_ms} * 1000); }
std::int64_t deadline_of(const timespec* timeout) { return timeout == nullptr ? no_deadline : after(micros_up(*timeout)); }
std::int64_t absolute_deadline(clockid_t clock, const timespec& when) {
  const std::int64_t at = micros_up(when) - origin_of(clock);
  return at < 0 ? 0 : at;
}

// ---------------------------------------------------------------- the control channel

struct ThreadChannel {
  int fd = -1;
  std::uint64_t seq = 0;
  // Who sends, read once per channel (getpid and gettid are system calls, and every message
  // carries them); a fork's child opens a new channel, so they are read again there.
  pid_t pid = 0;
  pid_t tid = 0;
  ~ThreadChannel() {
    if (fd >= 0) REAL(close)(fd);
  }
};
thread_local ThreadChannel channel;

void send_message(ShimMessage& message) {
  message.pid = channel.pid;
  message.tid = static_cast<std::int32_t>(channel.tid);
  (void)REAL(send)(channel.fd, &message, sizeof message, MSG_NOSIGNAL);
}

bool ensure_channel(ShimKind greeting) {
  if (channel.fd >= 0) return true;
  const int fd = socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0);
  if (fd < 0) return false;
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::memcpy(address.sun_path, socket_path, sizeof address.sun_path);
  if (REAL(connect)(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    REAL(close)(fd);
    return false;
  }
  channel.fd = fd;
  channel.pid = getpid();
  channel.tid = gettid();
  ShimMessage hello{};
  hello.kind = greeting;
  send_message(hello);
  return true;
}

int channel_fd() { return channel.fd; }
std::uint64_t next_seq() { return ++channel.seq; }
std::uint64_t current_seq() { return channel.seq; }

void say_running(std::uint64_t seq) {
  ShimMessage running{};
  running.kind = ShimKind::running;
  running.seq = seq;
  send_message(running);
}

void lost_controller() {
  active = false;
  if (channel.fd >= 0) REAL(close)(channel.fd);
  channel.fd = -1;
}

bool is_tagged(int fd) { return find_tagged(fd) != nullptr; }
int real_ppoll_call(pollfd* fds, nfds_t count, const timespec* timeout, const sigset_t* sigmask) {
  return REAL(ppoll)(fds, count, timeout, sigmask);
}

// The bytes written to every OCP socket, for the controller to collect when all threads wait.
void add_written(ShimMessage& message) {
  message.reported = 0;
  if (tagged_count.load(std::memory_order_relaxed) == 0) return;
  for (Tagged& entry : tagged) {
    if (entry.fd.load(std::memory_order_relaxed) < 0 || message.reported >= ocp::vtime::max_reported) continue;
    // The end first: a write made between the two loads is then reported whole.
    const std::uint64_t first_write_end = entry.first_write_end.exchange(0);
    message.written[message.reported++] = {entry.port.load(), entry.no_delay.load() ? 1u : 0u, entry.written.load(),
                                           first_write_end};
  }
}

// Waits (bounded) until every byte the controller wrote to our OCP sockets has arrived in
// their receive queues, so that looking at the sockets sees this instant's deliveries.
void await_deliveries() {
  if (tagged_count.load(std::memory_order_relaxed) == 0) return;
  const std::uint32_t count = page->connections.load(std::memory_order_acquire);
  for (Tagged& entry : tagged) {
    const int fd = entry.fd.load(std::memory_order_relaxed);
    if (fd < 0) continue;
    const std::uint32_t port = entry.port.load();
    for (std::uint32_t i = 0; i < count && i < static_cast<std::uint32_t>(ocp::vtime::max_connections); ++i) {
      if (page->delivered[i].port.load() != port) continue;
      const std::uint64_t wanted = page->delivered[i].delivered.load(std::memory_order_acquire);
      for (int spins = 0; spins < 200'000; ++spins) {
        tcp_info info{};
        socklen_t size = sizeof info;
        if (getsockopt(fd, IPPROTO_TCP, TCP_INFO, &info, &size) != 0 || info.tcpi_bytes_received >= wanted) break;
        if (info.tcpi_state != 1) break;   // TCP_ESTABLISHED: a closed socket gets nothing more
        sched_yield();
      }
    }
  }
}

// Makes every virtual timerfd whose deadline has come readable.
// Makes the timerfd readable now: TFD_IOC_SET_TICKS sets its expiration count and wakes its
// waiters at once, with no real timer (programming one is costly on a virtual machine: it was
// the client's largest cost); without it (a kernel without CONFIG_CHECKPOINT_RESTORE), the
// timer is armed for 1 ns and waited for.
#ifndef TFD_IOC_SET_TICKS
#define TFD_IOC_SET_TICKS _IOW('T', 0, std::uint64_t)   // <linux/timerfd.h>, which clashes with glibc's
#endif
void make_readable(int fd) {
  const std::uint64_t one = 1;
  if (ioctl(fd, TFD_IOC_SET_TICKS, &one) == 0) return;
  itimerspec soon{};
  soon.it_value.tv_nsec = 1;
  REAL(timerfd_settime)(fd, 0, &soon, nullptr);
  pollfd ready{fd, POLLIN, 0};
  for (int spins = 0; spins < 100'000 && REAL(poll)(&ready, 1, 0) == 0; ++spins) sched_yield();
}

void fire_due_timers() {
  if (timers_used == 0) return;
  const std::int64_t now = now_us();
  pthread_mutex_lock(&timers_lock);
  for (int fd = 0; fd < timers_end; ++fd) {
    VirtualTimer& timer = timers[fd];
    if (!timer.used || timer.deadline_us > now) continue;
    make_readable(fd);
    timer.fired = true;
    if (timer.interval_us > 0) {
      timer.deadline_us += ((now - timer.deadline_us) / timer.interval_us + 1) * timer.interval_us;
    } else {
      timer.deadline_us = no_deadline;
    }
  }
  pthread_mutex_unlock(&timers_lock);
}

std::int64_t earliest_timer() {
  if (timers_used == 0) return no_deadline;
  std::int64_t earliest = no_deadline;
  pthread_mutex_lock(&timers_lock);
  for (int fd = 0; fd < timers_end; ++fd) {
    if (timers[fd].used && timers[fd].deadline_us < earliest) earliest = timers[fd].deadline_us;
  }
  pthread_mutex_unlock(&timers_lock);
  return earliest;
}

// A real timeout of zero for the non-blocking looks.
const timespec zero_timeout{0, 0};

int sleep_until(std::int64_t deadline) {
  return virtual_wait(WaitKind::sleep, deadline, nullptr, 0, nullptr, [] { return 0; });
}

}  // namespace ocp_vtime_shim

// ---------------------------------------------------------------- lifecycle

namespace ocp_vtime_shim __attribute__((visibility("hidden"))) {

void reset_after_fork() {
  // The parent's control connection is shared with the child: the child gets its own.
  if (channel.fd >= 0) REAL(close)(channel.fd);
  channel.fd = -1;
  channel.seq = 0;
  forget_waker_after_fork();   // threads do not survive a fork: the child starts its own
  ensure_channel();
}

__attribute__((constructor)) void start_shim() {
  const char* path = getenv(ocp::vtime::socket_env);
  const char* clock = getenv(ocp::vtime::clock_env);
  if (path == nullptr || clock == nullptr || std::strlen(path) >= sizeof socket_path) return;
  const int fd = open(clock, O_RDONLY | O_CLOEXEC);
  if (fd < 0) return;
  void* mapped = mmap(nullptr, sizeof(ClockPage), PROT_READ, MAP_SHARED, fd, 0);
  REAL(close)(fd);
  if (mapped == MAP_FAILED) return;
  page = static_cast<const ClockPage*>(mapped);
  std::memcpy(socket_path, path, std::strlen(path) + 1);
  active = true;
  pthread_atfork(nullptr, nullptr, reset_after_fork);
  ensure_channel();
}

}  // namespace ocp_vtime_shim

using namespace ocp_vtime_shim;

// ---------------------------------------------------------------- time reads

extern "C" {

int clock_gettime(clockid_t clock, timespec* ts) {
  if (!active || is_cpu_clock(clock) || ts == nullptr) return REAL(clock_gettime)(clock, ts);
  *ts = to_timespec(origin_of(clock) + now_us());
  return 0;
}

int gettimeofday(timeval* tv, void* tz) {
  if (!active || tv == nullptr) return REAL(gettimeofday)(tv, tz);
  const std::int64_t us = ocp::vtime::realtime_origin_us + now_us();
  tv->tv_sec = static_cast<time_t>(us / 1'000'000);
  tv->tv_usec = static_cast<suseconds_t>(us % 1'000'000);
  return 0;
}

time_t time(time_t* out) {
  if (!active) return REAL(time)(out);
  const time_t seconds = static_cast<time_t>((ocp::vtime::realtime_origin_us + now_us()) / 1'000'000);
  if (out != nullptr) *out = seconds;
  return seconds;
}

// ---------------------------------------------------------------- sleeps

int nanosleep(const timespec* request, timespec* remaining) {
  if (!active) return REAL(nanosleep)(request, remaining);
  if (request == nullptr || request->tv_nsec < 0 || request->tv_nsec >= 1'000'000'000 || request->tv_sec < 0) {
    errno = EINVAL;
    return -1;
  }
  const std::int64_t deadline = deadline_of(request);
  if (sleep_until(deadline) < 0) {
    if (remaining != nullptr) *remaining = to_timespec(deadline - now_us());
    return -1;
  }
  return 0;
}

int clock_nanosleep(clockid_t clock, int flags, const timespec* request, timespec* remaining) {
  if (!active || is_cpu_clock(clock)) return REAL(clock_nanosleep)(clock, flags, request, remaining);
  if (request == nullptr || request->tv_nsec < 0 || request->tv_nsec >= 1'000'000'000) return EINVAL;
  const std::int64_t deadline = (flags & TIMER_ABSTIME) ? absolute_deadline(clock, *request) : deadline_of(request);
  if (sleep_until(deadline) < 0) {
    const int error = errno;
    if (remaining != nullptr && !(flags & TIMER_ABSTIME)) *remaining = to_timespec(deadline - now_us());
    return error;
  }
  return 0;
}

int usleep(useconds_t micros) {
  if (!active) return REAL(usleep)(micros);
  return sleep_until(after(micros)) < 0 ? -1 : 0;
}

unsigned sleep(unsigned seconds) {
  if (!active) return REAL(sleep)(seconds);
  const std::int64_t deadline = after(std::int64_t{seconds} * 1'000'000);
  if (sleep_until(deadline) < 0) return static_cast<unsigned>((deadline - now_us() + 999'999) / 1'000'000);
  return 0;
}

// ---------------------------------------------------------------- poll and select

int ppoll(pollfd* fds, nfds_t count, const timespec* timeout, const sigset_t* sigmask) {
  if (!active || count > static_cast<nfds_t>(max_watched)) return REAL(ppoll)(fds, count, timeout, sigmask);
  return virtual_wait(WaitKind::poll, deadline_of(timeout), fds, static_cast<int>(count), sigmask,
                      [&] { return REAL(ppoll)(fds, count, &zero_timeout, sigmask); });
}

int poll(pollfd* fds, nfds_t count, int timeout_ms) {
  if (!active || count > static_cast<nfds_t>(max_watched)) return REAL(poll)(fds, count, timeout_ms);
  return virtual_wait(WaitKind::poll, deadline_of_ms(timeout_ms), fds, static_cast<int>(count), nullptr,
                      [&] { return REAL(poll)(fds, count, 0); });
}

int __poll_chk(pollfd* fds, nfds_t count, int timeout_ms, size_t) { return poll(fds, count, timeout_ms); }
int __ppoll_chk(pollfd* fds, nfds_t count, const timespec* timeout, const sigset_t* sigmask, size_t) {
  return ppoll(fds, count, timeout, sigmask);
}

}  // extern "C"

namespace ocp_vtime_shim __attribute__((visibility("hidden"))) {

// select's sets as pollfds, to wait on them beside the control channel; false when too many.
bool sets_to_pollfds(int nfds, const fd_set* in, const fd_set* out, const fd_set* except, pollfd* fds, int& count) {
  count = 0;
  for (int fd = 0; fd < nfds && fd < FD_SETSIZE; ++fd) {
    short events = 0;
    if (in != nullptr && FD_ISSET(fd, in)) events |= POLLIN;
    if (out != nullptr && FD_ISSET(fd, out)) events |= POLLOUT;
    if (except != nullptr && FD_ISSET(fd, except)) events |= POLLPRI;
    if (events == 0) continue;
    if (count == max_watched) return false;
    fds[count++] = {fd, events, 0};
  }
  return true;
}

int select_virtually(int nfds, fd_set* in, fd_set* out, fd_set* except, std::int64_t deadline, const sigset_t* sigmask) {
  pollfd fds[max_watched];
  int count = 0;
  if (!sets_to_pollfds(nfds, in, out, except, fds, count)) return -2;
  fd_set saved[3];
  if (in != nullptr) saved[0] = *in;
  if (out != nullptr) saved[1] = *out;
  if (except != nullptr) saved[2] = *except;
  return virtual_wait(WaitKind::select, deadline, fds, count, sigmask, [&] {
    if (in != nullptr) *in = saved[0];
    if (out != nullptr) *out = saved[1];
    if (except != nullptr) *except = saved[2];
    return REAL(pselect)(nfds, in, out, except, &zero_timeout, sigmask);
  });
}

// A new OCP socket: the program's TCP_NODELAY (set before connect, as libuv may) becomes the
// shim's, and the real socket's is turned on.
bool take_over_no_delay(int fd) {
  int value = 0;
  socklen_t size = sizeof value;
  const bool on = REAL(getsockopt)(fd, IPPROTO_TCP, TCP_NODELAY, &value, &size) == 0 && value != 0;
  const int yes = 1;
  (void)REAL(setsockopt)(fd, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);
  return on;
}

}  // namespace ocp_vtime_shim

extern "C" {

int select(int nfds, fd_set* in, fd_set* out, fd_set* except, timeval* timeout) {
  if (active) {
    const std::int64_t deadline =
        timeout == nullptr ? no_deadline : after(std::int64_t{timeout->tv_sec} * 1'000'000 + timeout->tv_usec);
    const int result = select_virtually(nfds, in, out, except, deadline, nullptr);
    if (result != -2) {
      if (result == 0 && timeout != nullptr) *timeout = timeval{0, 0};
      return result;
    }
  }
  return REAL(select)(nfds, in, out, except, timeout);
}

int pselect(int nfds, fd_set* in, fd_set* out, fd_set* except, const timespec* timeout, const sigset_t* sigmask) {
  if (active) {
    const int result = select_virtually(nfds, in, out, except, deadline_of(timeout), sigmask);
    if (result != -2) return result;
  }
  return REAL(pselect)(nfds, in, out, except, timeout, sigmask);
}

// ---------------------------------------------------------------- epoll

int epoll_pwait(int epfd, epoll_event* events, int max_events, int timeout_ms, const sigset_t* sigmask) {
  if (!active) return REAL(epoll_pwait)(epfd, events, max_events, timeout_ms, sigmask);
  const pollfd watch{epfd, POLLIN, 0};
  return virtual_wait(WaitKind::epoll, deadline_of_ms(timeout_ms), &watch, 1, sigmask,
                      [&] { return REAL(epoll_pwait)(epfd, events, max_events, 0, sigmask); });
}

int epoll_wait(int epfd, epoll_event* events, int max_events, int timeout_ms) {
  if (!active) return REAL(epoll_wait)(epfd, events, max_events, timeout_ms);
  return epoll_pwait(epfd, events, max_events, timeout_ms, nullptr);
}

// ---------------------------------------------------------------- timerfd

int timerfd_create(int clock, int flags) {
  const int fd = REAL(timerfd_create)(clock, flags);
  if (!active || fd < 0 || fd >= max_timer_fds || is_cpu_clock(clock)) return fd;
  pthread_mutex_lock(&timers_lock);
  timers[fd] = VirtualTimer{true, clock, no_deadline, 0, false};
  ++timers_used;
  if (fd >= timers_end) timers_end = fd + 1;
  pthread_mutex_unlock(&timers_lock);
  return fd;
}

int timerfd_settime(int fd, int flags, const itimerspec* value, itimerspec* old) {
  if (!active || fd < 0 || fd >= max_timer_fds || value == nullptr) return REAL(timerfd_settime)(fd, flags, value, old);
  pthread_mutex_lock(&timers_lock);
  VirtualTimer& timer = timers[fd];
  if (!timer.used) {
    pthread_mutex_unlock(&timers_lock);
    return REAL(timerfd_settime)(fd, flags, value, old);
  }
  const std::int64_t now = now_us();
  if (old != nullptr) {
    old->it_interval = to_timespec(timer.interval_us);
    old->it_value = to_timespec(timer.deadline_us == no_deadline ? 0 : (timer.deadline_us > now ? timer.deadline_us - now : 1));
  }
  // The real timer is never armed: it is set only to clear expirations the program did not read.
  const itimerspec disarm{};
  const int result = timer.fired ? REAL(timerfd_settime)(fd, 0, &disarm, nullptr) : 0;
  timer.fired = false;
  if (result == 0) {
    const bool armed = value->it_value.tv_sec != 0 || value->it_value.tv_nsec != 0;
    timer.interval_us = micros_up(value->it_interval);
    if (!armed) {
      timer.deadline_us = no_deadline;
    } else if (flags & TFD_TIMER_ABSTIME) {
      timer.deadline_us = absolute_deadline(timer.clock, value->it_value);
    } else {
      timer.deadline_us = now + micros_up(value->it_value);
    }
  }
  pthread_mutex_unlock(&timers_lock);
  if (result == 0) fire_due_timers();
  return result;
}

int timerfd_gettime(int fd, itimerspec* value) {
  if (!active || fd < 0 || fd >= max_timer_fds || value == nullptr || !timers[fd].used) return REAL(timerfd_gettime)(fd, value);
  pthread_mutex_lock(&timers_lock);
  const VirtualTimer& timer = timers[fd];
  const std::int64_t now = now_us();
  value->it_interval = to_timespec(timer.interval_us);
  value->it_value = to_timespec(timer.deadline_us == no_deadline ? 0 : (timer.deadline_us > now ? timer.deadline_us - now : 1));
  pthread_mutex_unlock(&timers_lock);
  return 0;
}

// ---------------------------------------------------------------- OCP sockets

int connect(int fd, const sockaddr* address, socklen_t length) {
  const int result = REAL(connect)(fd, address, length);
  if (!active || (result != 0 && errno != EINPROGRESS) || address == nullptr) return result;
  const int error = errno;
  bool loopback = false;
  if (address->sa_family == AF_INET && length >= sizeof(sockaddr_in)) {
    loopback = (ntohl(reinterpret_cast<const sockaddr_in*>(address)->sin_addr.s_addr) >> 24) == 127;
  } else if (address->sa_family == AF_INET6 && length >= sizeof(sockaddr_in6)) {
    const in6_addr& ip = reinterpret_cast<const sockaddr_in6*>(address)->sin6_addr;
    loopback = IN6_IS_ADDR_LOOPBACK(&ip) || (IN6_IS_ADDR_V4MAPPED(&ip) && ip.s6_addr[12] == 127);
  }
  if (loopback && result != 0) {
    // Loopback's handshake completes in the kernel's own time: wait for it here, so that the
    // connection exists (or was refused) at this virtual instant, whatever the machine's load.
    pollfd done{fd, POLLOUT, 0};
    for (int spins = 0; spins < 100'000 && REAL(poll)(&done, 1, 0) == 0; ++spins) sched_yield();
  }
  if (loopback) {
    sockaddr_storage local{};
    socklen_t size = sizeof local;
    if (getsockname(fd, reinterpret_cast<sockaddr*>(&local), &size) == 0) {
      const std::uint32_t port = local.ss_family == AF_INET ? ntohs(reinterpret_cast<sockaddr_in*>(&local)->sin_port)
                                                            : ntohs(reinterpret_cast<sockaddr_in6*>(&local)->sin6_port);
      for (Tagged& entry : tagged) {
        int empty = -1;
        if (entry.fd.load() != -1) continue;
        entry.port = port;
        entry.written = 0;
        entry.first_write_end = 0;
        entry.no_delay = take_over_no_delay(fd);
        if (!entry.fd.compare_exchange_strong(empty, fd)) continue;
        tagged_count.fetch_add(1);
        if (ensure_channel()) {
          ShimMessage connected{};
          connected.kind = ShimKind::connected;
          connected.port = port;
          connected.remote_port = address->sa_family == AF_INET ? ntohs(reinterpret_cast<const sockaddr_in*>(address)->sin_port)
                                                                 : ntohs(reinterpret_cast<const sockaddr_in6*>(address)->sin6_port);
          send_message(connected);
        }
        break;
      }
    }
  }
  errno = error;
  return result;
}

int close(int fd) {
  if (active && fd >= 0) {
    if (Tagged* entry = find_tagged(fd)) {
      const std::uint32_t port = entry->port.load();
      const int result = REAL(close)(fd);
      entry->fd = -1;
      tagged_count.fetch_sub(1);
      if (ensure_channel()) {
        ShimMessage closed{};
        closed.kind = ShimKind::closed;
        closed.port = port;
        send_message(closed);
      }
      return result;
    }
    if (fd < max_timer_fds && timers[fd].used) {
      pthread_mutex_lock(&timers_lock);
      timers[fd].used = false;
      --timers_used;
      pthread_mutex_unlock(&timers_lock);
    }
  }
  return REAL(close)(fd);
}

}  // extern "C"

namespace ocp_vtime_shim __attribute__((visibility("hidden"))) {
ssize_t count_written(int fd, ssize_t result) {
  if (result > 0) {
    if (Tagged* entry = find_tagged(fd)) {
      const std::uint64_t end = entry->written.fetch_add(static_cast<std::uint64_t>(result)) + static_cast<std::uint64_t>(result);
      std::uint64_t none = 0;
      entry->first_write_end.compare_exchange_strong(none, end);
    }
  }
  return result;
}

bool is_no_delay_option(int level, int name) { return level == IPPROTO_TCP && name == TCP_NODELAY; }
}  // namespace ocp_vtime_shim

extern "C" {

ssize_t write(int fd, const void* data, size_t size) { return count_written(fd, REAL(write)(fd, data, size)); }
ssize_t writev(int fd, const iovec* parts, int count) { return count_written(fd, REAL(writev)(fd, parts, count)); }
ssize_t send(int fd, const void* data, size_t size, int flags) { return count_written(fd, REAL(send)(fd, data, size, flags)); }
ssize_t sendto(int fd, const void* data, size_t size, int flags, const sockaddr* to, socklen_t length) {
  return count_written(fd, REAL(sendto)(fd, data, size, flags, to, length));
}
ssize_t sendmsg(int fd, const msghdr* message, int flags) { return count_written(fd, REAL(sendmsg)(fd, message, flags)); }

// TCP_NODELAY of an OCP socket is the program's, kept by the shim (Tagged); the real one stays on.
int setsockopt(int fd, int level, int name, const void* value, socklen_t length) {
  if (active && is_no_delay_option(level, name) && value != nullptr && length >= sizeof(int)) {
    if (Tagged* entry = find_tagged(fd)) {
      entry->no_delay = *static_cast<const int*>(value) != 0;
      return 0;
    }
  }
  return REAL(setsockopt)(fd, level, name, value, length);
}

int getsockopt(int fd, int level, int name, void* value, socklen_t* length) {
  if (active && is_no_delay_option(level, name) && value != nullptr && length != nullptr && *length >= sizeof(int)) {
    if (Tagged* entry = find_tagged(fd)) {
      *static_cast<int*>(value) = entry->no_delay.load() ? 1 : 0;
      *length = sizeof(int);
      return 0;
    }
  }
  return REAL(getsockopt)(fd, level, name, value, length);
}

}  // extern "C"
