// The wait for quiescence, the /proc looks and the limits of the Controller
// (controller_impl.hpp; docs/virtual-time.md, "Quiescence").
#include <sched.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <string>

#include "controller_impl.hpp"
#include "sim_app/proc_stat.hpp"

namespace ocp::vtime {

bool Controller::Impl::all_blocked_by_record() const {
  for (const auto& [fd, thread] : threads) {
    if (!thread.blocked) return false;
  }
  return true;
}

// Every thread said it waits, or is one we did not wake and that said nothing since it last
// ran on its own: it is most likely asleep in a wait the shim does not wrap (a mutex, a
// futex with no timeout: tokio's and V8's idle threads), so /proc may be asked at once. A
// thread we woke will speak (BLOCKED or RUNNING) before it sleeps: it is waited for.
bool Controller::Impl::none_woken_silent() const {
  for (const auto& [fd, thread] : threads) {
    if (!thread.blocked && thread.woken_by_us) return false;
  }
  return true;
}

// The processes to look at: every one with a shim, and the launched ones and their children
// without one yet (a shell script that runs the client, a program between exec and its hello).
std::vector<pid_t> Controller::Impl::watched_pids() {
  std::vector<pid_t> pids;
  for (const auto& [pid, process] : processes) pids.push_back(pid);
  std::map<pid_t, Clock::time_point> still_unshimmed;
  for (const Expected& launched : expected) {
    for (const pid_t pid : proc.process_tree(launched.pid, max_processes)) {
      if (processes.contains(pid)) continue;
      pids.push_back(pid);
      const auto seen = unshimmed.find(pid);
      still_unshimmed[pid] = seen == unshimmed.end() ? Clock::now() : seen->second;
    }
  }
  unshimmed = std::move(still_unshimmed);
  return pids;
}

// A process of the client's tree that has run without the shim for handshake_timeout (a
// static binary; a program the shell started that dropped LD_PRELOAD) cannot live in
// virtual time. (A zombie waiting for its parent is not running.)
void Controller::Impl::check_unshimmed() {
  for (const auto& [pid, since] : unshimmed) {
    if (Clock::now() - since <= options.handshake_timeout) continue;
    char path[64];
    std::snprintf(path, sizeof path, "/proc/%d/stat", static_cast<int>(pid));
    const std::string text = sim_app::read_small_proc_file(path);   // bounded, as every file read
    const auto open_paren = text.find('(');
    const auto close_paren = text.rfind(')');
    if (open_paren == std::string::npos || close_paren == std::string::npos || close_paren + 2 >= text.size()) continue;
    if (text[close_paren + 2] == 'Z' || text[close_paren + 2] == 'X') continue;
    if (runnable(pid)) continue;   // still starting, perhaps starved of CPU: refused once it waits
    const std::string name = text.substr(open_paren + 1, close_paren - open_paren - 1);
    throw VirtualTimeError("the client's process " + std::to_string(pid) + " (" + name +
                           ") cannot run in virtual time (no shim handshake within " +
                           std::to_string(options.handshake_timeout.count()) +
                           " ms: a static binary, or a runtime that does not call libc for time, such as Go); use --time real");
  }
}

// A thread of `pid` is running or waits for a CPU. The handshake timeout is wall time, and a
// loaded machine can starve a process's start-up (a shell at nice 19 beside stress-ng) past
// it: such a process is not refused while it runs, only once it waits without a shim.
bool Controller::Impl::runnable(pid_t pid) {
  for (const ThreadLook& thread : proc.look_at_threads(pid, false)) {
    if (thread.state == 'R') return true;
  }
  return false;
}

bool Controller::Impl::asleep_in_proc() {
  ++stats.proc_checks;
  const auto looking = Clock::now();
  const bool asleep = asleep_in_proc_now();
  stats.proc_us += static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - looking).count());
  return asleep;
}

bool Controller::Impl::asleep_in_proc_now() {
  if (pin && pin->cpu() >= 0) {
    if (const std::optional<bool> asleep = single_look()) {
      ++stats.single_looks;
      return *asleep;
    }
  }
  std::vector<pid_t> pids;
  std::vector<std::vector<ThreadLook>> first;
  {
    const ProcScanner::OneListing one_listing(proc);
    pids = watched_pids();
    for (const pid_t pid : pids) first.push_back(proc.look_at_threads(pid));
  }
  for (std::size_t i = 0; i < pids.size(); ++i) {
    if (!asleep_in_both(first[i], proc.look_at_threads(pids[i]))) return false;
  }
  // A process that forked just before the first look and fell asleep is asleep in both; its
  // child is not in `pids`: the same processes must still be all there are.
  return watched_pids() == pids;
}

// One look is a true picture when nothing of the clients' could run while it was taken:
// every thread may run on the controller's CPU only, and the controller was not switched out
// meanwhile. (Two looks and their run counts are what show it otherwise.) Empty when the
// look cannot tell: then two are taken.
std::optional<bool> Controller::Impl::single_look() {
  const ProcScanner::OneListing one_listing(proc);
  const long switches = own_switches();
  bool holds = true;
  for (const pid_t pid : watched_pids()) {
    for (const ThreadLook& thread : proc.look_at_threads(pid, false)) {
      if (thread.state == 'Z' || thread.state == 'X') continue;
      if (thread.state != 'S') return false;
      holds = holds && thread.cpu == pin->cpu() && pinned_here(thread.tid);
    }
  }
  if (!holds || own_switches() != switches) return std::nullopt;
  return true;
}

bool Controller::Impl::pinned_here(pid_t tid) {
  if (pinned_threads.size() > 4 * max_threads) pinned_threads.clear();   // bounded: ids of ended threads
  const auto [entry, added] = pinned_threads.try_emplace(tid, false);
  if (added) entry->second = pin->holds(tid);
  return entry->second;
}

long Controller::Impl::own_switches() {
  rusage usage{};
  getrusage(RUSAGE_THREAD, &usage);
  return usage.ru_nvcsw + usage.ru_nivcsw;
}

// Why the clients are not quiescent yet, for the wait trace.
std::string Controller::Impl::waiting_for() {
  std::string out;
  for (const auto& [fd, thread] : threads) {
    if (!thread.blocked) out += "thread " + std::to_string(thread.tid) + " (pid " + std::to_string(thread.pid) + ") runs; ";
  }
  if (expecting_a_greeting()) out += "a launched process has no shim yet; ";
  if (starting_up()) out += "a process is starting up; ";
  if (!unclaimed.empty()) out += "a connection no shim announced; ";
  out += "/proc: ";
  out += awake_description();
  out += "; watched:";
  for (const pid_t pid : watched_pids()) {
    out += ' ';
    out += std::to_string(pid);
  }
  return out;
}

std::string Controller::Impl::awake_description() {
  std::string out;
  for (const pid_t pid : watched_pids()) {
    const std::string awake = describe_awake(proc.look_at_threads(pid));
    if (!awake.empty()) out += (out.empty() ? "" : "; ") + std::string("pid ") + std::to_string(pid) + ": " + awake;
  }
  return out;
}

std::uint64_t Controller::Impl::client_cpu() {
  std::uint64_t total = 0;
  for (const pid_t pid : watched_pids()) {
    const std::uint64_t now = cpu_ticks(pid);
    std::uint64_t& seen = cpu_seen[pid];
    seen = std::max(seen, now);
  }
  for (const auto& [pid, ticks] : cpu_seen) total += ticks;
  return total;
}

void Controller::Impl::check_limits() {
  check_unshimmed();
  const auto now = Clock::now();
  if (now - run_started > options.watchdog) {
    throw VirtualTimeError("the world took more than " + std::to_string(options.watchdog.count() / 1000) +
                           " s of wall time (watchdog); client threads awake: " + awake_description());
  }
  for (Expected& launched : expected) {
    const bool silent = !launched.greeted || processes.empty();
    if (silent && launched.alive && launched.alive() && now - launched.launched > options.handshake_timeout &&
        !runnable(launched.pid)) {
      throw VirtualTimeError(launched.name + " cannot run in virtual time (no shim handshake within " +
                             std::to_string(options.handshake_timeout.count()) +
                             " ms: a static binary, or a runtime that does not call libc for time, such as Go); use --time real");
    }
    if (!silent) launched.launched = now;   // the clock restarts for a later exec
  }
  for (const Unclaimed& connection : unclaimed) {
    if (now - connection.since > options.handshake_timeout) {
      throw VirtualTimeError("a process connected from port " + std::to_string(connection.port) +
                             " without the shim: it cannot run in virtual time (a static binary, or a child that "
                             "dropped LD_PRELOAD); use --time real");
    }
  }
}

// A client that never lets the instant end: a busy loop, or a wait the shim cannot see that
// spins. Found by its CPU since the wait for quiescence began (read first at the first check,
// so that a short wait reads no CPU at all), or, when a loaded machine starves it so that it
// never burns that much, by the wall time.
void Controller::Impl::check_busy(Clock::time_point settle_began, std::optional<std::uint64_t>& cpu_at_start) {
  static const std::uint64_t ticks_per_second = static_cast<std::uint64_t>(sysconf(_SC_CLK_TCK));
  const std::uint64_t cpu = client_cpu();
  if (!cpu_at_start) cpu_at_start = cpu;
  const std::uint64_t used_ms = (cpu - std::min(cpu, *cpu_at_start)) * 1000 / ticks_per_second;
  const auto waited = Clock::now() - settle_began;
  if (used_ms > static_cast<std::uint64_t>(options.busy_cpu.count())) {
    throw VirtualTimeError("the client used " + std::to_string(used_ms) +
                           " ms of CPU without ever waiting (a busy loop, or a wait the shim cannot see); awake: " +
                           awake_description());
  }
  if (waited > options.busy_wall) {
    throw VirtualTimeError("the client ran for " + std::to_string(std::chrono::duration_cast<std::chrono::seconds>(waited).count()) +
                           " s of wall time without ever waiting (" + std::to_string(used_ms) +
                           " ms of CPU: a busy loop on a loaded machine, or a wait the shim cannot see); awake: " +
                           awake_description());
  }
}

// A process that has not waited through the shim yet, has no child to wait for, and began
// less than a second ago is starting up (a program importing its modules, a shell between two
// commands): its threads may all be asleep for a moment (a pipe, a lock) while it is busy, and
// virtual time must not advance then, or the instant it connects would depend on the
// machine's load. After a second a process that never waits through the shim counts as
// waiting where the shim does not see, as any thread does.
bool Controller::Impl::starting_up() {
  const auto now = Clock::now();
  for (const auto& [pid, process] : processes) {
    if (process.waited || now - process.began > std::chrono::seconds(1)) continue;
    if (proc.process_tree(pid, 2).size() < 2) return true;
  }
  return false;
}

// A live process of the client's tree without a shim (between an exec and its hello, or a
// static binary): virtual time waits for its hello, or for check_unshimmed to refuse it after
// the handshake timeout — however fast the world would otherwise end. A zombie is not alive.
bool Controller::Impl::unshimmed_alive() {
  for (const auto& [pid, since] : unshimmed) {
    for (const ThreadLook& thread : proc.look_at_threads(pid)) {
      if (thread.state != 'Z' && thread.state != 'X') return true;
    }
  }
  return false;
}

bool Controller::Impl::expecting_a_greeting() const {
  for (const Expected& launched : expected) {
    if ((!launched.greeted || processes.empty()) && launched.alive && launched.alive()) return true;
  }
  return false;
}

// Waits until every client thread waits. The shim's messages say so for the waits it wraps;
// /proc says so for every thread, wrapped or not (a thread the record still has running is in
// a wait the shim cannot see: a mutex, a blocking read). Processes that exited count as waiting.
void Controller::Impl::settle() {
  ++stats.settles;
  const auto began = Clock::now();
  std::optional<std::uint64_t> cpu_at_start;
  int naps = 0;
  int quiet = 0;   // 1 ms waits in a row without a message
  for (int round = 0;; ++round) {
    pump(0);
    const bool all_said_so = all_blocked_by_record();
    // /proc is looked at only when it can say yes: every thread said it waits, or the one
    // that runs has been silent a while (it may be in a wait the shim does not wrap).
    if ((all_said_so || quiet >= 2 || none_woken_silent()) && !expecting_a_greeting() && unclaimed.empty() && !starting_up() && asleep_in_proc() &&
        !unshimmed_alive()) {
      pump(0);   // what a thread sent before it fell asleep
      break;
    }
    if ((round & 15) == 15) {
      check_limits();
      check_busy(began, cpu_at_start);
      if (trace.is_open() && (round & 4095) == 4095) trace_line("still waiting for quiescence: " + waiting_for());
    }
    if (!all_said_so && !none_woken_silent()) {
      quiet = pump(1) ? 0 : quiet + 1;   // mostly, the next BLOCKED ends this wait at once
      continue;
    }
    // Every thread said it waits, or those that did not will not (they run or sleep where the
    // shim does not see), and one is not asleep yet: it is on its way. No message will say
    // when it gets there, so look again soon (a 1 ms wait for a message was most of a
    // tokio client's wall time).
    if (naps < 20) {
      sched_yield();
    } else {
      const timespec nap{0, naps < 200 ? 20'000 : 500'000};
      nanosleep(&nap, nullptr);
    }
    ++naps;
  }
}

}  // namespace ocp::vtime
