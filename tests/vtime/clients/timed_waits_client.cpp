// Every timed wait on an object the shim wraps, once timing out and once ended early by
// another thread, measured on the (virtual) monotonic clock. One line each on stdout:
//     NAME result=R elapsed_us=N
// VirtualTimeClients.TimedWaitsEndAtTheirVirtualDeadline reads them: in virtual time each
// elapsed time is exact. The waits are made as programs make them: through libc's exported
// functions (libstdc++'s condition_variable and timed_mutex among them), and a futex through
// syscall(), as Rust's std does.
#include <linux/futex.h>
#include <pthread.h>
#include <semaphore.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <thread>

namespace {

using namespace std::chrono_literals;

std::int64_t now_us(clockid_t clock = CLOCK_MONOTONIC) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return std::int64_t{ts.tv_sec} * 1'000'000 + ts.tv_nsec / 1000;
}

timespec in(std::int64_t micros, clockid_t clock) {
  const std::int64_t at = now_us(clock) + micros;
  return timespec{static_cast<time_t>(at / 1'000'000), static_cast<long>(at % 1'000'000) * 1000};
}

void report(const char* name, long result, std::int64_t started) {
  std::printf("%s result=%ld elapsed_us=%lld\n", name, result, static_cast<long long>(now_us() - started));
  std::fflush(stdout);
}

// Runs `wait` now, and `other` on a second thread; reports what the wait returned and when.
template <class Wait, class Other>
void measure(const char* name, Wait&& wait, Other&& other) {
  std::thread helper(other);
  const std::int64_t started = now_us();
  const long result = wait();
  report(name, result, started);
  helper.join();
}
void nothing() {}

pthread_cond_t realtime_cond = PTHREAD_COND_INITIALIZER;
pthread_mutex_t cond_mutex = PTHREAD_MUTEX_INITIALIZER;

void condition_variables() {
  measure("cond_timedwait_timeout", [] {
    pthread_mutex_lock(&cond_mutex);
    const timespec deadline = in(250'000, CLOCK_REALTIME);
    const int result = pthread_cond_timedwait(&realtime_cond, &cond_mutex, &deadline);
    pthread_mutex_unlock(&cond_mutex);
    return result;
  }, nothing);
  std::mutex mutex;
  std::condition_variable cv;
  bool ready = false;
  measure("cv_wait_for_timeout", [&] {
    std::unique_lock lock(mutex);
    return static_cast<long>(cv.wait_for(lock, 100ms) == std::cv_status::timeout ? ETIMEDOUT : 0);
  }, nothing);
  measure("cv_wait_for_notified", [&] {
    std::unique_lock lock(mutex);
    return static_cast<long>(cv.wait_for(lock, 500ms, [&] { return ready; }) ? 0 : ETIMEDOUT);
  }, [&] {
    std::this_thread::sleep_for(30ms);
    std::lock_guard lock(mutex);
    ready = true;
    cv.notify_one();
  });
}

void semaphores() {
  sem_t sem;
  sem_init(&sem, 0, 0);
  measure("sem_timedwait_timeout", [&] {
    const timespec deadline = in(70'000, CLOCK_REALTIME);
    return sem_timedwait(&sem, &deadline) == 0 ? 0L : static_cast<long>(errno);
  }, nothing);
  measure("sem_clockwait_posted", [&] {
    const timespec deadline = in(500'000, CLOCK_MONOTONIC);
    return sem_clockwait(&sem, CLOCK_MONOTONIC, &deadline) == 0 ? 0L : static_cast<long>(errno);
  }, [&] {
    std::this_thread::sleep_for(20ms);
    sem_post(&sem);
  });
  sem_destroy(&sem);
}

void timed_locks() {
  std::timed_mutex mutex;
  std::atomic<bool> held{false};
  auto hold_for = [&](std::chrono::milliseconds how_long) {
    return [&, how_long] {
      std::lock_guard lock(mutex);
      held = true;
      std::this_thread::sleep_for(how_long);
    };
  };
  auto try_lock_for = [&](std::chrono::milliseconds patience) {
    return [&, patience] {
      while (!held) std::this_thread::yield();   // the other thread holds it first (no virtual time passes)
      const bool got = mutex.try_lock_for(patience);
      if (got) mutex.unlock();
      held = false;
      return got ? 0L : static_cast<long>(ETIMEDOUT);
    };
  };
  measure("timedlock_acquired", try_lock_for(100ms), hold_for(40ms));
  measure("timedlock_timeout", try_lock_for(50ms), hold_for(200ms));
}

// pthread_rwlock_timed{rd,wr}lock and pthread_rwlock_clock{rd,wr}lock, against a thread that
// holds the lock the other way (a writer against readers, a reader against a writer).
void reader_writer_locks() {
  pthread_rwlock_t rwlock = PTHREAD_RWLOCK_INITIALIZER;
  std::atomic<bool> held{false};
  auto hold_for = [&](bool write, std::chrono::milliseconds how_long) {
    return [&, write, how_long] {
      if (write) {
        pthread_rwlock_wrlock(&rwlock);
      } else {
        pthread_rwlock_rdlock(&rwlock);
      }
      held = true;
      std::this_thread::sleep_for(how_long);
      pthread_rwlock_unlock(&rwlock);
    };
  };
  auto lock_within = [&](bool write, bool clock_form, std::int64_t patience_us) {
    return [&, write, clock_form, patience_us] {
      while (!held) std::this_thread::yield();   // the other thread holds it first (no virtual time passes)
      const clockid_t clock = clock_form ? CLOCK_MONOTONIC : CLOCK_REALTIME;
      const timespec deadline = in(patience_us, clock);
      int result = 0;
      if (clock_form) {
        result = write ? pthread_rwlock_clockwrlock(&rwlock, clock, &deadline) : pthread_rwlock_clockrdlock(&rwlock, clock, &deadline);
      } else {
        result = write ? pthread_rwlock_timedwrlock(&rwlock, &deadline) : pthread_rwlock_timedrdlock(&rwlock, &deadline);
      }
      if (result == 0) pthread_rwlock_unlock(&rwlock);
      held = false;
      return static_cast<long>(result);
    };
  };
  measure("rwlock_timedwrlock_timeout", lock_within(true, false, 50'000), hold_for(false, 200ms));
  measure("rwlock_timedrdlock_timeout", lock_within(false, false, 60'000), hold_for(true, 200ms));
  measure("rwlock_clockrdlock_acquired", lock_within(false, true, 500'000), hold_for(true, 40ms));
  measure("rwlock_clockwrlock_acquired", lock_within(true, true, 500'000), hold_for(false, 30ms));
  pthread_rwlock_destroy(&rwlock);
}

long futex_wait(std::atomic<std::uint32_t>& word, int op, const timespec* timeout) {
  const long result = syscall(SYS_futex, &word, op | FUTEX_PRIVATE_FLAG, 0u, timeout, nullptr, FUTEX_BITSET_MATCH_ANY);
  return result == 0 ? 0L : static_cast<long>(errno);
}

void futex_words() {
  std::atomic<std::uint32_t> word{0};
  measure("futex_wait_timeout", [&] {
    const timespec relative{0, 60'000'000};
    return futex_wait(word, FUTEX_WAIT, &relative);
  }, nothing);
  measure("futex_bitset_timeout", [&] {
    const timespec deadline = in(80'000, CLOCK_MONOTONIC);
    return futex_wait(word, FUTEX_WAIT_BITSET, &deadline);
  }, nothing);
  measure("futex_bitset_woken", [&] {
    const timespec deadline = in(900'000, CLOCK_MONOTONIC);
    long result = 0;
    while (word.load() == 0 && result != ETIMEDOUT) result = futex_wait(word, FUTEX_WAIT_BITSET, &deadline);
    return result == EAGAIN ? 0L : result;
  }, [&] {
    std::this_thread::sleep_for(10ms);
    word = 1;
    syscall(SYS_futex, &word, FUTEX_WAKE | FUTEX_PRIVATE_FLAG, 1, nullptr, nullptr, 0);
  });
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && (std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0)) {
    std::puts("usage: vtime_timed_waits_client\n  every timed wait on an object, once timed out and once ended early: NAME result=R elapsed_us=N");
    return 0;
  }
  if (argc > 1) {
    std::fprintf(stderr, "vtime_timed_waits_client: takes no arguments (unknown option %s)\n", argv[1]);
    return 2;
  }
  condition_variables();
  semaphores();
  timed_locks();
  reader_writer_locks();
  futex_words();
  std::printf("done\n");
  std::fflush(stdout);
  pause();   // the world ends it
}
