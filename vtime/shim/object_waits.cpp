// Waits on an object, on the simulator's clock (docs/virtual-time.md): pthread_cond_timedwait
// and pthread_cond_clockwait, sem_timedwait and sem_clockwait, pthread_mutex_timedlock and
// pthread_mutex_clocklock, pthread_rwlock_timed/clock{rd,wr}lock, and futex waits with a timeout made through syscall() (Rust's std
// and tokio park threads that way).
//
// Such a wait sleeps in the kernel on the object (a futex word), where the control socket does
// not reach. So the thread says BLOCKED(virtual deadline, the object) and waits with no real
// timeout. When virtual time reaches the deadline, the controller tells the process's waker (a
// thread started on the first such wait, always asleep in recv on its own connection), which
// wakes the object for real: a broadcast, or a FUTEX_WAKE of every waiter (spurious wakeups are
// allowed for all of them). The woken thread finds it was the waker and times out. A real
// signal from another thread wakes it as in real time; it then says RUNNING (and /proc sees it
// run before it says so). The controller wakes only at a quiescent instant, when the waiter
// really is in its wait.
//
// The waker never touches an object its waiter has left (it is often on the waiter's stack):
// each waiting thread has a slot, holding its wait under a small lock; the waker wakes the
// object holding that lock, and only for the wait the controller named; the waiter clears the
// slot under the same lock before it returns.
//
// The semaphore and mutex loops follow glibc's own protocol on its futex words (glibc >= 2.25,
// 64-bit): a semaphore's value and waiter count in one 64-bit word; a mutex's lock word 0/1/2
// (2: waiters, so the unlock wakes one). Robust, priority-inheriting and priority-protecting
// mutexes have other protocols: their timed locks go to libc unchanged (not virtualised).
// A reader-writer lock's protocol (glibc's phases on three futex words) is left to glibc: the
// waiter calls glibc's own timed lock with a deadline the shim owns (in its slot), far in the
// future; the waker moves that deadline to the past and wakes the three words, and glibc,
// waiting again, times out and backs out as it always does.
#include <linux/futex.h>
#include <pthread.h>
#include <sched.h>
#include <semaphore.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdarg>

#include "shim_core.hpp"

namespace ocp_vtime_shim __attribute__((visibility("hidden"))) {

namespace {   // this file's libc functions
int (*real_pthread_cond_wait)(pthread_cond_t*, pthread_mutex_t*);
int (*real_pthread_cond_timedwait)(pthread_cond_t*, pthread_mutex_t*, const timespec*);
int (*real_pthread_cond_clockwait)(pthread_cond_t*, pthread_mutex_t*, clockid_t, const timespec*);
int (*real_pthread_cond_broadcast)(pthread_cond_t*);
int (*real_sem_trywait)(sem_t*);
int (*real_sem_timedwait)(sem_t*, const timespec*);
int (*real_sem_clockwait)(sem_t*, clockid_t, const timespec*);
int (*real_pthread_mutex_trylock)(pthread_mutex_t*);
int (*real_pthread_mutex_timedlock)(pthread_mutex_t*, const timespec*);
int (*real_pthread_mutex_clocklock)(pthread_mutex_t*, clockid_t, const timespec*);
int (*real_pthread_rwlock_clockrdlock)(pthread_rwlock_t*, clockid_t, const timespec*);
int (*real_pthread_rwlock_clockwrlock)(pthread_rwlock_t*, clockid_t, const timespec*);
long (*real_syscall)(long, ...);
}  // namespace


long futex(void* word, int op, unsigned value, unsigned bitset = FUTEX_BITSET_MATCH_ANY) {
  return REAL(syscall)(SYS_futex, word, op, value, nullptr, nullptr, bitset);
}

// ---------------------------------------------------------------- slots

constexpr int max_slots = 1024;   // as many as the controller tracks threads

struct WaitSlot {
  std::atomic<pid_t> owner{0};   // the thread that holds it (0: free)
  std::atomic<bool> locked{false};
  std::uint64_t seq = 0;         // the wait registered (0: none)
  bool woken = false;            // the waker ended it
  WaitKind kind = WaitKind::none;
  void* object = nullptr;
  std::uint32_t futex_flags = 0;
  timespec rwlock_deadline{};    // a reader-writer lock wait: the real deadline glibc waits to
};
WaitSlot slots[max_slots];

void lock(WaitSlot& slot) {
  while (slot.locked.exchange(true, std::memory_order_acquire)) sched_yield();
}
void unlock(WaitSlot& slot) { slot.locked.store(false, std::memory_order_release); }

struct SlotHolder {
  int index = -1;
  ~SlotHolder() {
    if (index >= 0) slots[index].owner.store(0, std::memory_order_release);
  }
};
thread_local SlotHolder my_slot;

WaitSlot* claim_slot() {
  if (my_slot.index >= 0) return &slots[my_slot.index];
  const pid_t tid = gettid();
  for (int i = 0; i < max_slots; ++i) {
    pid_t free = 0;
    if (slots[i].owner.compare_exchange_strong(free, tid)) {
      my_slot.index = i;
      return &slots[i];
    }
  }
  return nullptr;
}

// Wakes the object for real (the waker, or everybody when the controller went away).
void wake_object(WaitSlot& slot) {
  if (slot.kind == WaitKind::cond) {
    REAL(pthread_cond_broadcast)(static_cast<pthread_cond_t*>(slot.object));
  } else if (slot.kind == WaitKind::rwlock) {
    __atomic_store_n(&slot.rwlock_deadline.tv_sec, 0, __ATOMIC_RELEASE);   // the past: glibc's next wait times out
    auto& data = static_cast<pthread_rwlock_t*>(slot.object)->__data;
    unsigned* words[] = {&data.__readers, &data.__wrphase_futex, &data.__writers_futex};
    for (unsigned* word : words) {
      futex(word, FUTEX_WAKE | static_cast<int>(slot.futex_flags), INT_MAX);
    }
  } else {
    futex(slot.object, FUTEX_WAKE | static_cast<int>(slot.futex_flags), INT_MAX);
  }
}

// ---------------------------------------------------------------- the waker

enum WakerState : int { no_waker = 0, waker_starting = 1, waker_running = 2, waker_failed = 3 };
std::atomic<int> waker_state{no_waker};

void wake_slot(std::uint32_t index, std::uint64_t seq) {
  if (index >= static_cast<std::uint32_t>(max_slots) || seq == 0) return;
  WaitSlot& slot = slots[index];
  lock(slot);
  if (slot.seq == seq) {
    slot.woken = true;
    wake_object(slot);
  }
  unlock(slot);
}

// The controller went away: every waiter wakes (they see real time from now on).
void wake_everybody() {
  for (WaitSlot& slot : slots) {
    lock(slot);
    if (slot.seq != 0) wake_object(slot);
    unlock(slot);
  }
}

void* waker_main(void*) {
  sigset_t all;
  sigfillset(&all);
  pthread_sigmask(SIG_BLOCK, &all, nullptr);   // the program's signals go to its own threads
  if (!ensure_channel(ShimKind::waker_hello)) {
    waker_state.store(waker_failed, std::memory_order_release);
    return nullptr;
  }
  waker_state.store(waker_running, std::memory_order_release);
  const int fd = channel_fd();
  for (;;) {
    ControlMessage message{};
    const ssize_t got = recv(fd, &message, sizeof message, 0);
    if (got == static_cast<ssize_t>(sizeof message)) {
      wake_slot(message.on_object.slot, message.seq);
    } else if (got == 0 || (got < 0 && errno != EINTR)) {
      lost_controller();
      wake_everybody();
      return nullptr;
    }
  }
}

// Started once per process, on the first wait on an object; its hello is sent before the
// waiter's BLOCKED, so the controller knows it when the deadline comes.
bool ensure_waker() {
  int state = waker_state.load(std::memory_order_acquire);
  if (state == waker_running) return true;
  if (state == no_waker && waker_state.compare_exchange_strong(state, waker_starting)) {
    pthread_attr_t attributes;
    pthread_attr_init(&attributes);
    pthread_attr_setdetachstate(&attributes, PTHREAD_CREATE_DETACHED);
    pthread_attr_setstacksize(&attributes, 64 * 1024);
    pthread_t thread;
    if (pthread_create(&thread, &attributes, waker_main, nullptr) != 0) waker_state.store(waker_failed);
    pthread_attr_destroy(&attributes);
  }
  while ((state = waker_state.load(std::memory_order_acquire)) == waker_starting) sched_yield();
  return state == waker_running;
}

// ---------------------------------------------------------------- one wait on an object

struct Outcome {
  bool virtualised = false;   // false: no slot, waker or controller; the caller goes to libc
  bool woken = false;         // the waker ended it: the deadline came
  long result = 0;            // the real wait's
  int error = 0;
};

// Says BLOCKED(deadline, object), makes the real wait `wait` (with no timeout), and leaves the
// slot. The caller made sure the deadline is still ahead.
template <class Wait>
Outcome object_wait(WaitKind kind, void* object, std::uint32_t futex_flags, std::int64_t deadline, Wait&& wait) {
  Outcome outcome;
  WaitSlot* slot = claim_slot();
  if (slot == nullptr || !ensure_channel() || !ensure_waker()) return outcome;
  ShimMessage blocked{};
  blocked.kind = ShimKind::blocked;
  blocked.wait = kind;
  blocked.seq = next_seq();
  blocked.deadline_us = deadline;
  blocked.on_object = {static_cast<std::uint32_t>(slot - slots), futex_flags, reinterpret_cast<std::uintptr_t>(object)};
  add_written(blocked);
  lock(*slot);
  slot->seq = blocked.seq;
  slot->woken = false;
  slot->kind = kind;
  slot->object = object;
  slot->futex_flags = futex_flags;
  unlock(*slot);
  send_message(blocked);
  outcome.result = wait();
  outcome.error = errno;
  lock(*slot);
  outcome.woken = slot->woken;
  slot->seq = 0;
  unlock(*slot);
  // Also after the waker's wake: the controller then knows at once that this thread runs, and
  // need not wait for a message before it asks /proc.
  if (active.load(std::memory_order_relaxed)) say_running(blocked.seq);
  outcome.virtualised = true;
  errno = outcome.error;
  return outcome;
}

bool bad_time(const timespec* when) { return when == nullptr || when->tv_nsec < 0 || when->tv_nsec >= 1'000'000'000; }

// ---------------------------------------------------------------- condition variables

// glibc keeps the condition variable's clock in bit 1 of __wrefs (pthread_condattr_setclock).
clockid_t clock_of(const pthread_cond_t* cond) {
  const unsigned flags = __atomic_load_n(&cond->__data.__wrefs, __ATOMIC_RELAXED);
  return (flags & 2) != 0 ? CLOCK_MONOTONIC : CLOCK_REALTIME;
}

int cond_wait_until(pthread_cond_t* cond, pthread_mutex_t* mutex, std::int64_t deadline, clockid_t clock,
                    const timespec* abstime) {
  if (deadline <= now_us()) return ETIMEDOUT;
  const Outcome outcome = object_wait(WaitKind::cond, cond, 0, deadline, [&] { return REAL(pthread_cond_wait)(cond, mutex); });
  if (!outcome.virtualised) return REAL(pthread_cond_clockwait)(cond, mutex, clock, abstime);
  if (outcome.woken || deadline <= now_us()) return ETIMEDOUT;
  return static_cast<int>(outcome.result);
}

// ---------------------------------------------------------------- semaphores

// glibc's sem_t (64-bit): the value in the low half of a 64-bit word, the waiters in the high
// half; the futex is the value's 32 bits; then `private` (0: private to the process).
constexpr unsigned waiter_shift = 32;
std::atomic<std::uint64_t>& sem_data(sem_t* sem) { return *reinterpret_cast<std::atomic<std::uint64_t>*>(sem); }
std::uint32_t sem_futex_flags(const sem_t* sem) { return reinterpret_cast<const int*>(sem)[2] == 0 ? FUTEX_PRIVATE_FLAG : 0; }

int sem_wait_until(sem_t* sem, std::int64_t deadline, clockid_t clock, const timespec* abstime) {
  if (REAL(sem_trywait)(sem) == 0) return 0;
  if (deadline <= now_us()) {
    errno = ETIMEDOUT;
    return -1;
  }
  std::atomic<std::uint64_t>& data = sem_data(sem);
  std::uint64_t d = data.fetch_add(std::uint64_t{1} << waiter_shift, std::memory_order_relaxed) + (std::uint64_t{1} << waiter_shift);
  int error = 0;
  for (;;) {
    if ((d & 0xffff'ffffu) != 0) {
      if (data.compare_exchange_weak(d, d - 1 - (std::uint64_t{1} << waiter_shift), std::memory_order_acquire)) return 0;
      continue;
    }
    if (deadline <= now_us()) {
      error = ETIMEDOUT;
      break;
    }
    const std::uint32_t flags = sem_futex_flags(sem);
    const Outcome outcome = object_wait(WaitKind::semaphore, sem, flags, deadline, [&] {
      return futex(sem, FUTEX_WAIT | static_cast<int>(flags), 0);
    });
    if (!outcome.virtualised) {
      data.fetch_sub(std::uint64_t{1} << waiter_shift, std::memory_order_relaxed);
      return REAL(sem_clockwait)(sem, clock, abstime);
    }
    if (outcome.result < 0 && outcome.error == EINTR) {
      error = EINTR;
      break;
    }
    d = data.load(std::memory_order_relaxed);
  }
  data.fetch_sub(std::uint64_t{1} << waiter_shift, std::memory_order_relaxed);
  errno = error;
  return -1;
}

// ---------------------------------------------------------------- timed locks

constexpr int mutex_robust = 16, mutex_priority_inherit = 32, mutex_priority_protect = 64, mutex_shared = 128;

int mutex_lock_until(pthread_mutex_t* mutex, std::int64_t deadline, clockid_t clock, const timespec* abstime) {
  const int kind = mutex->__data.__kind;
  if (kind & (mutex_robust | mutex_priority_inherit | mutex_priority_protect)) {
    return REAL(pthread_mutex_clocklock)(mutex, clock, abstime);   // another protocol: not virtualised
  }
  const int tried = REAL(pthread_mutex_trylock)(mutex);
  if (tried != EBUSY) return tried;
  if ((kind & 3) == PTHREAD_MUTEX_ERRORCHECK && mutex->__data.__owner == gettid()) return EDEADLK;
  auto* word = reinterpret_cast<std::atomic<int>*>(&mutex->__data.__lock);
  const std::uint32_t flags = (kind & mutex_shared) ? 0 : FUTEX_PRIVATE_FLAG;
  for (;;) {
    // As glibc's own waiters: 2 says "someone waits", so the unlock wakes one of us.
    if (word->exchange(2, std::memory_order_acquire) == 0) {
      mutex->__data.__owner = gettid();
      ++mutex->__data.__nusers;
      if ((kind & 3) == PTHREAD_MUTEX_RECURSIVE) mutex->__data.__count = 1;
      return 0;
    }
    if (deadline <= now_us()) return ETIMEDOUT;
    const Outcome outcome = object_wait(WaitKind::lock, word, flags, deadline, [&] {
      return futex(word, FUTEX_WAIT | static_cast<int>(flags), 2);
    });
    if (!outcome.virtualised) return REAL(pthread_mutex_clocklock)(mutex, clock, abstime);
  }
}

// ---------------------------------------------------------------- reader-writer locks

// glibc's timed rwlock lock, `lock` (its clockrdlock or clockwrlock), until the virtual
// `deadline`: first a look (the deadline already past: glibc then acquires, fails with
// EDEADLK, or times out at once), then the wait on the slot's own real deadline.
int rwlock_until(pthread_rwlock_t* rwlock, std::int64_t deadline,
                 int (*lock)(pthread_rwlock_t*, clockid_t, const timespec*), clockid_t clock, const timespec* abstime) {
  const timespec past{0, 0};
  const int looked = lock(rwlock, CLOCK_MONOTONIC, &past);
  if (looked != ETIMEDOUT || deadline <= now_us()) return looked;
  WaitSlot* slot = claim_slot();
  if (slot == nullptr) return lock(rwlock, clock, abstime);
  ::ocp_vtime_shim::lock(*slot);
  slot->rwlock_deadline = timespec{4'000'000'000, 0};   // 127 years of the real monotonic clock: never, for real
  ::ocp_vtime_shim::unlock(*slot);
  const std::uint32_t flags = rwlock->__data.__shared != 0 ? 0 : FUTEX_PRIVATE_FLAG;
  const Outcome outcome = object_wait(WaitKind::rwlock, rwlock, flags, deadline,
                                      [&] { return lock(rwlock, CLOCK_MONOTONIC, &slot->rwlock_deadline); });
  if (!outcome.virtualised) return lock(rwlock, clock, abstime);
  return static_cast<int>(outcome.result);   // 0 (acquired, also when the waker came too late), ETIMEDOUT, EDEADLK
}

// ---------------------------------------------------------------- futex words (syscall)

bool futex_virtually(long* args, long& result) {
  const int op = static_cast<int>(args[1]);
  const int command = op & FUTEX_CMD_MASK;
  const auto* timeout = reinterpret_cast<const timespec*>(args[3]);
  if ((command != FUTEX_WAIT && command != FUTEX_WAIT_BITSET) || bad_time(timeout) || timeout->tv_sec < 0) return false;
  const std::int64_t deadline = command == FUTEX_WAIT
                                    ? after(micros_up(*timeout))
                                    : absolute_deadline((op & FUTEX_CLOCK_REALTIME) ? CLOCK_REALTIME : CLOCK_MONOTONIC, *timeout);
  auto* word = reinterpret_cast<std::atomic<std::uint32_t>*>(args[0]);
  const auto expected = static_cast<std::uint32_t>(args[2]);
  result = -1;
  if (word->load(std::memory_order_relaxed) != expected) {
    errno = EAGAIN;
    return true;
  }
  if (deadline <= now_us()) {
    errno = ETIMEDOUT;
    return true;
  }
  const std::uint32_t flags = static_cast<std::uint32_t>(op & FUTEX_PRIVATE_FLAG);
  const Outcome outcome = object_wait(WaitKind::futex, word, flags, deadline, [&] {
    return futex(word, command | static_cast<int>(flags), expected, static_cast<unsigned>(args[5]));
  });
  if (!outcome.virtualised) return false;
  if (outcome.woken) {
    errno = ETIMEDOUT;
    return true;
  }
  result = outcome.result;
  errno = outcome.error;
  return true;
}

}  // namespace ocp_vtime_shim

namespace ocp_vtime_shim __attribute__((visibility("hidden"))) {
// After fork the child has one thread and no waker: it starts its own on its first wait.
void forget_waker_after_fork() {
  waker_state.store(no_waker);
  for (WaitSlot& slot : slots) {
    slot.owner.store(0);
    slot.locked.store(false);
    slot.seq = 0;
  }
  my_slot.index = -1;
}
}  // namespace ocp_vtime_shim

using namespace ocp_vtime_shim;

extern "C" {

int pthread_cond_clockwait(pthread_cond_t* cond, pthread_mutex_t* mutex, clockid_t clock, const timespec* abstime) {
  if (!active || bad_time(abstime) || (clock != CLOCK_MONOTONIC && clock != CLOCK_REALTIME)) {
    return REAL(pthread_cond_clockwait)(cond, mutex, clock, abstime);
  }
  return cond_wait_until(cond, mutex, absolute_deadline(clock, *abstime), clock, abstime);
}

int pthread_cond_timedwait(pthread_cond_t* cond, pthread_mutex_t* mutex, const timespec* abstime) {
  if (!active || bad_time(abstime)) return REAL(pthread_cond_timedwait)(cond, mutex, abstime);
  const clockid_t clock = clock_of(cond);
  return cond_wait_until(cond, mutex, absolute_deadline(clock, *abstime), clock, abstime);
}

int sem_clockwait(sem_t* sem, clockid_t clock, const timespec* abstime) {
  if (!active || bad_time(abstime) || (clock != CLOCK_MONOTONIC && clock != CLOCK_REALTIME)) {
    return REAL(sem_clockwait)(sem, clock, abstime);
  }
  return sem_wait_until(sem, absolute_deadline(clock, *abstime), clock, abstime);
}

int sem_timedwait(sem_t* sem, const timespec* abstime) {
  if (!active || bad_time(abstime)) return REAL(sem_timedwait)(sem, abstime);
  return sem_wait_until(sem, absolute_deadline(CLOCK_REALTIME, *abstime), CLOCK_REALTIME, abstime);
}

int pthread_mutex_clocklock(pthread_mutex_t* mutex, clockid_t clock, const timespec* abstime) {
  if (!active || bad_time(abstime) || (clock != CLOCK_MONOTONIC && clock != CLOCK_REALTIME)) {
    return REAL(pthread_mutex_clocklock)(mutex, clock, abstime);
  }
  return mutex_lock_until(mutex, absolute_deadline(clock, *abstime), clock, abstime);
}

int pthread_mutex_timedlock(pthread_mutex_t* mutex, const timespec* abstime) {
  if (!active || bad_time(abstime)) return REAL(pthread_mutex_timedlock)(mutex, abstime);
  return mutex_lock_until(mutex, absolute_deadline(CLOCK_REALTIME, *abstime), CLOCK_REALTIME, abstime);
}

int pthread_rwlock_clockrdlock(pthread_rwlock_t* rwlock, clockid_t clock, const timespec* abstime) {
  if (!active || bad_time(abstime) || (clock != CLOCK_MONOTONIC && clock != CLOCK_REALTIME)) {
    return REAL(pthread_rwlock_clockrdlock)(rwlock, clock, abstime);
  }
  return rwlock_until(rwlock, absolute_deadline(clock, *abstime), REAL(pthread_rwlock_clockrdlock), clock, abstime);
}

int pthread_rwlock_clockwrlock(pthread_rwlock_t* rwlock, clockid_t clock, const timespec* abstime) {
  if (!active || bad_time(abstime) || (clock != CLOCK_MONOTONIC && clock != CLOCK_REALTIME)) {
    return REAL(pthread_rwlock_clockwrlock)(rwlock, clock, abstime);
  }
  return rwlock_until(rwlock, absolute_deadline(clock, *abstime), REAL(pthread_rwlock_clockwrlock), clock, abstime);
}

// The timed forms are glibc's clock forms on CLOCK_REALTIME.
int pthread_rwlock_timedrdlock(pthread_rwlock_t* rwlock, const timespec* abstime) {
  return pthread_rwlock_clockrdlock(rwlock, CLOCK_REALTIME, abstime);
}

int pthread_rwlock_timedwrlock(pthread_rwlock_t* rwlock, const timespec* abstime) {
  return pthread_rwlock_clockwrlock(rwlock, CLOCK_REALTIME, abstime);
}

// syscall() itself: futex waits with a timeout are virtual, and a close goes through the shim's
// own close() (libuv closes every descriptor with syscall(SYS_close) to dodge cancellation: the
// shim must still see an OCP socket close, or its connection table fills after 16 reconnects);
// everything else goes to libc. The six arguments are read whatever the call takes (they are
// registers on the ABIs we run on).
long syscall(long number, ...) {
  va_list list;
  va_start(list, number);
  long args[6];
  for (long& arg : args) arg = va_arg(list, long);
  va_end(list);
  if (number == SYS_close && active) return close(static_cast<int>(args[0]));
  if (number == SYS_futex && active) {
    long result = 0;
    if (futex_virtually(args, result)) return result;
  }
  return REAL(syscall)(number, args[0], args[1], args[2], args[3], args[4], args[5]);
}

}  // extern "C"
