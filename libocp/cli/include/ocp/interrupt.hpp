#pragma once
// Ctrl-C, the same in every tool (docs/usage.md, "Exit codes"): the first SIGINT, SIGTERM or
// SIGHUP (a closed SSH session, a CI runner's cancel) asks the run to stop. The tool then finishes what it can report, prints "interrupted",
// marks its reports `"interrupted": true` and exits 130. A second signal (a second later or
// more) ends the process at once (still 130), after an optional async-signal-safe cleanup such
// as killing launched clients.
#include <signal.h>
#include <time.h>
#include <unistd.h>

#include <atomic>

#include "ocp/exit_codes.hpp"

namespace ocp::cli {

namespace detail {
inline std::atomic<int> interrupt_signals{0};
inline std::atomic<long long> first_interrupt_ns{0};
inline void (*interrupt_cleanup)() = nullptr;

inline long long monotonic_ns() {   // clock_gettime is async-signal-safe
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<long long>(now.tv_sec) * 1'000'000'000LL + now.tv_nsec;
}

// A repeat within this time is the same Ctrl-C delivered twice, not a second one: `timeout`
// signals its child and then its whole process group, and a terminal signals every process of
// the foreground group.
inline constexpr long long same_interrupt_ns = 1'000'000'000LL;

extern "C" inline void on_interrupt_signal(int) {
  const long long now = monotonic_ns();
  if (interrupt_signals.fetch_add(1) == 0) {
    first_interrupt_ns.store(now);
    return;
  }
  if (now - first_interrupt_ns.load() < same_interrupt_ns) return;
  if (interrupt_cleanup) interrupt_cleanup();
  _exit(exit_interrupted);
}
}  // namespace detail

// `cleanup` runs only on the second signal, just before _exit: it must be async-signal-safe.
// SIGPIPE is ignored from then on. Call again after something else handled the signals (an Asio signal_set puts the default
// action back when it ends); the count of signals so far is kept.
inline void install_interrupt_handlers(void (*cleanup)() = nullptr) {
  static_assert(std::atomic<int>::is_always_lock_free && std::atomic<long long>::is_always_lock_free);
  detail::interrupt_cleanup = cleanup;
  struct sigaction action {};
  action.sa_handler = detail::on_interrupt_signal;
  action.sa_flags = SA_RESTART;   // the reports being written are not cut short by the signal
  sigemptyset(&action.sa_mask);
  for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) sigaction(signal_number, &action, nullptr);
  // A closed stdout (`| head`) is a failed write, not the end: the reports still get written.
  signal(SIGPIPE, SIG_IGN);
}

inline bool interrupt_requested() { return detail::interrupt_signals.load() > 0; }

// For tests, and for a tool that learns of the signal another way (an Asio signal_set).
inline void request_interrupt() { detail::interrupt_signals.fetch_add(1); }

}  // namespace ocp::cli
