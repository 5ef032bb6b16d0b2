// The virtual-time controller (controller.hpp).
#include "vtime/controller.hpp"

#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sched.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <set>
#include <thread>
#include <utility>

#include "clock_page.hpp"
#include "cpu_pin.hpp"
#include "proc_scan.hpp"
#include "socket_stream.hpp"
#include "vtime/protocol.hpp"

namespace ocp::vtime {

namespace {

using Clock = std::chrono::steady_clock;

constexpr std::size_t max_threads = 1024;        // client threads tracked, all processes
constexpr std::size_t max_processes = 64;
constexpr std::size_t max_same_instant_rounds = 100'000;

std::string errno_text() { return std::strerror(errno); }

}  // namespace

struct Controller::Impl {
  struct ThreadRecord {
    pid_t pid = 0;
    pid_t tid = 0;
    bool blocked = false;
    std::uint64_t seq = 0;
    std::uint64_t seq_at_flush = 0;   // its wait when the simulator's bytes of the instant went out
    std::int64_t deadline = no_deadline;
    WaitKind wait = WaitKind::none;
    bool waker = false;            // the process's waker: always in recv, wakes waits on objects
    bool woken_by_us = false;      // we woke it and it has not said anything since
    std::uint32_t slot = 0;        // a wait on an object: as its BLOCKED said
    std::uint64_t object = 0;
    std::uint32_t futex_flags = 0;
  };
  struct ProcessRecord {
    int threads = 0;
    // Not yet waited through the shim since its image began (its main thread's hello: a new
    // program, or a forked child): it is starting up (see starting_up()).
    bool waited = false;
    Clock::time_point began = Clock::now();
    std::map<std::uint32_t, ClientWrites> written;   // by the client's local port
    std::map<std::uint32_t, Clock::time_point> closed;   // OCP sockets it closed, not yet seen
  };
  struct Listener {
    int fd = -1;
    std::uint16_t port = 0;
    AcceptHandler on_accept;
  };
  struct Expected {
    pid_t pid;
    std::string name;
    std::function<bool()> alive;
    Clock::time_point launched;
    bool greeted = false;
  };
  struct Unclaimed {   // an accepted connection no shim said it made (yet)
    std::uint16_t port;
    Clock::time_point since;
  };

  VirtualExecutor& executor;
  ControllerOptions options;
  ControllerStats stats;
  std::string dir;
  std::string socket_path;
  std::string clock_path;
  int control_fd = -1;
  ClockPage* page = nullptr;
  std::map<int, ThreadRecord> threads;            // by control connection
  std::map<pid_t, ProcessRecord> processes;
  std::map<pid_t, int> wakers;                    // each process's waker, by its control connection
  ProcScanner proc;                               // the /proc looks, files kept open
  std::unique_ptr<CpuPin> pin;                    // null: not pinned
  std::map<pid_t, bool> pinned_threads;           // by thread id: may run on the pinned CPU only
  std::map<std::uint32_t, pid_t> connected_ports; // announced by a shim
  std::set<std::uint16_t> to_accept;              // connected to a listener of ours, not accepted yet
  std::vector<Listener> listeners;
  std::vector<std::shared_ptr<SocketStream>> streams;
  std::vector<Expected> expected;
  std::vector<Unclaimed> unclaimed;
  std::ofstream trace;
  Clock::time_point run_started;
  std::uint64_t accepted = 0;
  std::uint64_t sweeps = 0;                       // rounds, for the sweeps of every 64th
  bool thread_left = false;
  std::map<pid_t, std::uint64_t> cpu_seen;
  std::map<pid_t, Clock::time_point> unshimmed;   // in the client's tree, without the shim, since

  Impl(VirtualExecutor& executor_in, ControllerOptions options_in) : executor(executor_in), options(std::move(options_in)) {}

  // ------------------------------------------------------------ setup

  void open() {
    char pattern[] = "/tmp/ocp-vtime-XXXXXX";
    if (mkdtemp(pattern) == nullptr) throw VirtualTimeError("cannot make a folder for the control socket: " + errno_text());
    dir = pattern;
    socket_path = dir + "/control";
    clock_path = dir + "/clock";
    const int clock_fd = ::open(clock_path.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (clock_fd < 0 || ftruncate(clock_fd, sizeof(ClockPage)) != 0) throw VirtualTimeError("cannot make the clock page: " + errno_text());
    void* mapped = mmap(nullptr, sizeof(ClockPage), PROT_READ | PROT_WRITE, MAP_SHARED, clock_fd, 0);
    ::close(clock_fd);
    if (mapped == MAP_FAILED) throw VirtualTimeError("cannot map the clock page: " + errno_text());
    page = static_cast<ClockPage*>(mapped);
    page->now_us.store(executor.now().count());
    control_fd = socket(AF_UNIX, SOCK_SEQPACKET | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::snprintf(address.sun_path, sizeof address.sun_path, "%s", socket_path.c_str());
    if (control_fd < 0 || bind(control_fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 ||
        ::listen(control_fd, 128) != 0) {
      throw VirtualTimeError("cannot open the control socket: " + errno_text());
    }
    if (options.wait_trace_path.empty()) {
      if (const char* path = std::getenv("OCP_VTIME_WAIT_TRACE"); path != nullptr) options.wait_trace_path = path;
    }
    if (!options.wait_trace_path.empty()) trace.open(options.wait_trace_path, std::ios::trunc);
    const char* no_pin = std::getenv("OCP_VTIME_NO_PIN");
    if (options.pin_cpu && (no_pin == nullptr || std::strcmp(no_pin, "1") != 0)) pin = std::make_unique<CpuPin>();
  }

  ~Impl() {
    for (const Listener& listener : listeners) {
      if (listener.fd >= 0) ::close(listener.fd);
    }
    for (const auto& [fd, thread] : threads) ::close(fd);
    if (control_fd >= 0) ::close(control_fd);
    if (page != nullptr) munmap(page, sizeof(ClockPage));
    if (!dir.empty()) {
      ::unlink(socket_path.c_str());
      ::unlink(clock_path.c_str());
      ::rmdir(dir.c_str());
    }
  }

  void trace_line(const std::string& text) {
    if (!trace.is_open()) return;
    trace << executor.now().count() << " µs: " << text << '\n';
  }

  int open_listener(std::uint16_t port) {
    const int fd = socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    const int yes = 1;
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    address.sin_port = htons(port);
    if (fd < 0 || bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 || ::listen(fd, 16) != 0) {
      const std::string why = errno_text();
      if (fd >= 0) ::close(fd);
      throw VirtualTimeError("cannot listen on 127.0.0.1:" + std::to_string(port) + ": " + why);
    }
    return fd;
  }

  // ------------------------------------------------------------ messages from the shims

  void accept_threads() {
    for (;;) {
      const int fd = accept4(control_fd, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
      if (fd < 0) return;
      if (threads.size() >= max_threads) {
        ::close(fd);
        throw VirtualTimeError("more than " + std::to_string(max_threads) + " client threads: the limit of virtual time");
      }
      threads[fd] = ThreadRecord{};
    }
  }

  void forget_thread(int fd) {
    thread_left = true;
    const ThreadRecord thread = threads.at(fd);
    ::close(fd);
    threads.erase(fd);
    if (thread.pid == 0) return;
    if (thread.waker) wakers.erase(thread.pid);
    auto process = processes.find(thread.pid);
    if (process != processes.end() && --process->second.threads <= 0) processes.erase(process);
    trace_line("pid " + std::to_string(thread.pid) + " thread " + std::to_string(thread.tid) + " left");
  }

  void on_message(int fd, ThreadRecord& thread, const ShimMessage& message) {
    ++stats.messages;
    thread.woken_by_us = false;
    if (message.kind == ShimKind::hello || message.kind == ShimKind::waker_hello) {
      thread.pid = message.pid;
      thread.tid = message.tid;
      if (message.kind == ShimKind::waker_hello) {
        thread.waker = true;
        thread.blocked = true;   // for ever: it sleeps in recv until a wake comes
        wakers[message.pid] = fd;
      }
      if (processes.size() >= max_processes && !processes.contains(message.pid)) {
        throw VirtualTimeError("more than " + std::to_string(max_processes) + " client processes");
      }
      ProcessRecord& process = processes[message.pid];
      ++process.threads;
      if (message.tid == message.pid && message.kind == ShimKind::hello) {   // a new image, or a fork's child
        process.waited = false;
        process.began = Clock::now();
      }
      for (Expected& launched : expected) launched.greeted = true;
      trace_line("pid " + std::to_string(message.pid) + " thread " + std::to_string(message.tid) +
                 (thread.waker ? " hello (the waker)" : " hello"));
      return;
    }
    ProcessRecord& process = processes[thread.pid];
    for (std::uint32_t i = 0; i < message.reported && i < static_cast<std::uint32_t>(max_reported); ++i) {
      process.written[message.written[i].port].merge(message.written[i]);
    }
    switch (message.kind) {
      case ShimKind::blocked:
        process.waited = true;
        thread.blocked = true;
        thread.seq = message.seq;
        thread.deadline = message.deadline_us;
        thread.wait = message.wait;
        thread.slot = message.slot;
        thread.object = message.object;
        thread.futex_flags = message.futex_flags;
        if (trace.is_open()) {
          trace_line("thread " + std::to_string(thread.tid) + " waits in " + wait_name(message.wait) +
                     (message.deadline_us == no_deadline ? std::string(" with no deadline")
                                                         : " until " + std::to_string(message.deadline_us) + " µs"));
        }
        break;
      case ShimKind::running:
        if (message.seq == thread.seq) thread.blocked = false;
        trace_line("thread " + std::to_string(thread.tid) + " woke on its own");
        break;
      case ShimKind::connected:
        connected_ports[message.port] = thread.pid;
        for (const Listener& listener : listeners) {
          if (listener.fd >= 0 && listener.port == message.remote_port) to_accept.insert(static_cast<std::uint16_t>(message.port));
        }
        std::erase_if(unclaimed, [&](const Unclaimed& u) { return u.port == message.port; });
        trace_line("thread " + std::to_string(thread.tid) + " connected from port " + std::to_string(message.port));
        break;
      case ShimKind::closed:
        process.closed[message.port] = Clock::now();
        to_accept.erase(static_cast<std::uint16_t>(message.port));
        trace_line("thread " + std::to_string(thread.tid) + " closed port " + std::to_string(message.port));
        break;
      case ShimKind::hello:
      case ShimKind::waker_hello:
        break;
    }
  }

  // Reads every message waiting; with `wait_ms` > 0, first waits that long for one. True when
  // anything came.
  bool pump(int wait_ms) {
    bool any = false;
    // A second pass when a thread connected, so that its first messages are read with the rest.
    for (int pass = 0; pass < 2; ++pass) {
      if (pass == 1) accept_threads();
      std::vector<pollfd> fds;
      fds.push_back({control_fd, POLLIN, 0});
      for (const auto& [fd, thread] : threads) fds.push_back({fd, POLLIN, 0});
      if (::poll(fds.data(), fds.size(), pass == 0 ? wait_ms : 0) <= 0) return any;
      any = true;
      for (std::size_t i = 1; i < fds.size(); ++i) {
        if (fds[i].revents != 0) read_messages(fds[i].fd);
      }
      if (!(fds[0].revents & POLLIN)) break;
    }
    return any;
  }

  void read_messages(int fd) {
    for (;;) {
      ShimMessage message{};
      const ssize_t got = recv(fd, &message, sizeof message, MSG_DONTWAIT);
      if (got == static_cast<ssize_t>(sizeof message)) {
        on_message(fd, threads.at(fd), message);
        continue;
      }
      if (got == 0 || (got < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) forget_thread(fd);
      return;
    }
  }

  // ------------------------------------------------------------ quiescence

  bool all_blocked_by_record() const {
    for (const auto& [fd, thread] : threads) {
      if (!thread.blocked) return false;
    }
    return true;
  }

  // Every thread said it waits, or is one we did not wake and that said nothing since it last
  // ran on its own: it is most likely asleep in a wait the shim does not wrap (a mutex, a
  // futex with no timeout: tokio's and V8's idle threads), so /proc may be asked at once. A
  // thread we woke will speak (BLOCKED or RUNNING) before it sleeps: it is waited for.
  bool none_woken_silent() const {
    for (const auto& [fd, thread] : threads) {
      if (!thread.blocked && thread.woken_by_us) return false;
    }
    return true;
  }

  // The processes to look at: every one with a shim, and the launched ones and their children
  // without one yet (a shell script that runs the client, a program between exec and its hello).
  std::vector<pid_t> watched_pids() {
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
  void check_unshimmed() {
    for (const auto& [pid, since] : unshimmed) {
      if (Clock::now() - since <= options.handshake_timeout) continue;
      char path[64];
      std::snprintf(path, sizeof path, "/proc/%d/stat", static_cast<int>(pid));
      std::ifstream stat(path);
      std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
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
  bool runnable(pid_t pid) {
    for (const ThreadLook& thread : proc.look_at_threads(pid, false)) {
      if (thread.state == 'R') return true;
    }
    return false;
  }

  bool asleep_in_proc() {
    ++stats.proc_checks;
    const auto looking = Clock::now();
    const bool asleep = asleep_in_proc_now();
    stats.proc_us += static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - looking).count());
    return asleep;
  }

  bool asleep_in_proc_now() {
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
  std::optional<bool> single_look() {
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

  bool pinned_here(pid_t tid) {
    if (pinned_threads.size() > 4 * max_threads) pinned_threads.clear();   // bounded: ids of ended threads
    const auto [entry, added] = pinned_threads.try_emplace(tid, false);
    if (added) entry->second = pin->holds(tid);
    return entry->second;
  }

  static long own_switches() {
    rusage usage{};
    getrusage(RUSAGE_THREAD, &usage);
    return usage.ru_nvcsw + usage.ru_nivcsw;
  }

  // Why the clients are not quiescent yet, for the wait trace.
  std::string waiting_for() {
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

  std::string awake_description() {
    std::string out;
    for (const pid_t pid : watched_pids()) {
      const std::string awake = describe_awake(proc.look_at_threads(pid));
      if (!awake.empty()) out += (out.empty() ? "" : "; ") + std::string("pid ") + std::to_string(pid) + ": " + awake;
    }
    return out;
  }

  std::uint64_t client_cpu() {
    std::uint64_t total = 0;
    for (const pid_t pid : watched_pids()) {
      const std::uint64_t now = cpu_ticks(pid);
      std::uint64_t& seen = cpu_seen[pid];
      seen = std::max(seen, now);
    }
    for (const auto& [pid, ticks] : cpu_seen) total += ticks;
    return total;
  }

  void check_limits() {
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
  void check_busy(Clock::time_point settle_began, std::optional<std::uint64_t>& cpu_at_start) {
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
  bool starting_up() {
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
  bool unshimmed_alive() {
    for (const auto& [pid, since] : unshimmed) {
      for (const ThreadLook& thread : proc.look_at_threads(pid)) {
        if (thread.state != 'Z' && thread.state != 'X') return true;
      }
    }
    return false;
  }

  bool expecting_a_greeting() const {
    for (const Expected& launched : expected) {
      if ((!launched.greeted || processes.empty()) && launched.alive && launched.alive()) return true;
    }
    return false;
  }

  // Waits until every client thread waits. The shim's messages say so for the waits it wraps;
  // /proc says so for every thread, wrapped or not (a thread the record still has running is in
  // a wait the shim cannot see: a mutex, a blocking read). Processes that exited count as waiting.
  void settle() {
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

  // ------------------------------------------------------------ the OCP connections

  // Every connection a client made at this instant (the shim announced it: the kernel may not
  // have queued it yet under load, so wait for it, bounded).
  void accept_connections() {
    // A shim announces its connections; a process without one (refused after the handshake
    // timeout) is found by a sweep every 64 rounds.
    if (to_accept.empty() && (++sweeps & 63) != 0) return;
    const auto give_up = Clock::now() + std::chrono::seconds(1);
    accept_queued();
    while (!to_accept.empty() && Clock::now() < give_up) {
      std::vector<pollfd> fds;
      for (const Listener& listener : listeners) {
        if (listener.fd >= 0) fds.push_back({listener.fd, POLLIN, 0});
      }
      if (fds.empty()) break;
      (void)::poll(fds.data(), fds.size(), 1);
      accept_queued();
    }
    to_accept.clear();
  }

  void accept_queued() {
    for (Listener& listener : listeners) {
      while (listener.fd >= 0) {
        sockaddr_in peer{};
        socklen_t size = sizeof peer;
        const int fd = accept4(listener.fd, reinterpret_cast<sockaddr*>(&peer), &size, SOCK_NONBLOCK | SOCK_CLOEXEC);
        if (fd < 0) break;
        const std::uint16_t port = ntohs(peer.sin_port);
        to_accept.erase(port);
        auto stream = std::make_shared<SocketStream>(executor, fd, port, "127.0.0.1 (connection " + std::to_string(++accepted) + ")");
        if (!claim_delivery_slot(*page, port)) {
          throw VirtualTimeError("more than " + std::to_string(max_connections) + " OCP connections open at once in virtual time");
        }
        streams.push_back(stream);
        if (!connected_ports.contains(port)) unclaimed.push_back({port, Clock::now()});
        trace_line("accepted a connection from port " + std::to_string(port));
        executor.call_at(executor.now(), [on_accept = listener.on_accept, stream] { on_accept(stream); });
      }
    }
  }

  // What the clients wrote while they ran, handed to the simulator at this instant.
  bool take_from_clients() {
    accept_connections();
    bool any = false;
    // Each connection is read when its shim reported bytes or a close not taken yet; every 64th
    // round (and after a thread left: a process that ended closes without a word) all are.
    const bool sweep = (sweeps & 63) == 0 || std::exchange(thread_left, false);
    for (const std::shared_ptr<SocketStream>& stream : streams) {
      if (stream->finished()) continue;
      ClientWrites reported;   // of every process (a fork's child may write to its parent's connection)
      bool expect_eof = false;
      for (auto& [pid, process] : processes) {
        if (auto found = process.written.find(stream->peer_port()); found != process.written.end()) reported.take(found->second);
        if (process.closed.erase(stream->peer_port()) > 0) expect_eof = true;
      }
      if (!sweep && !expect_eof && reported.written <= stream->received_total()) continue;
      const auto taking = Clock::now();
      const std::size_t got = stream->take(reported, expect_eof);
      if (trace.is_open() && Clock::now() - taking > std::chrono::milliseconds(100)) {
        trace_line("waited for the client's bytes on port " + std::to_string(stream->peer_port()) + ": expected " +
                   std::to_string(reported.written) + (expect_eof ? " and its close" : "") + ", have " +
                   std::to_string(stream->received_total()));
      }
      stats.bytes_in += got;
      if (stream->take_eof_news() || got > 0) any = true;
    }
    return any;
  }

  // This instant's writes to the sockets; true when anything reached a client.
  bool flush_to_clients() {
    // The counts first: a thread the bytes wake (at once, on a shared CPU) waits until all of
    // this instant's bytes arrived, on every connection, before it looks at its sockets.
    for (const std::shared_ptr<SocketStream>& stream : streams) {
      if (stream->queued_bytes() > 0) publish_delivered(*page, stream->peer_port(), stream->written_total() + stream->queued_bytes());
    }
    for (auto& [fd, thread] : threads) thread.seq_at_flush = thread.seq;
    bool changed = false;
    for (const std::shared_ptr<SocketStream>& stream : streams) stats.bytes_out += stream->flush(changed);
    // As sent: fewer when a socket's buffer was full.
    for (const std::shared_ptr<SocketStream>& stream : streams) publish_delivered(*page, stream->peer_port(), stream->written_total());
    std::erase_if(streams, [&](const std::shared_ptr<SocketStream>& stream) {
      if (!stream->finished()) return false;
      release_delivery_slot(*page, stream->peer_port());
      return true;
    });
    return changed;
  }

  // ------------------------------------------------------------ waking

  void send_to(int fd, ThreadRecord& thread, ControlKind kind) {
    ControlMessage message{};
    message.kind = kind;
    message.seq = thread.seq;
    (void)send(fd, &message, sizeof message, MSG_NOSIGNAL | MSG_DONTWAIT);
    thread.blocked = false;
    thread.woken_by_us = true;
  }

  // A wait on an object ends through the process's waker, which wakes the object for real.
  // False when the waker has not said hello yet (the next round tries again).
  bool wake_through_waker(ThreadRecord& thread) {
    const auto waker = wakers.find(thread.pid);
    if (waker == wakers.end()) return false;
    ControlMessage message{};
    message.kind = ControlKind::wake;
    message.seq = thread.seq;
    message.wait = thread.wait;
    message.slot = thread.slot;
    message.object = thread.object;
    message.futex_flags = thread.futex_flags;
    message.tid = thread.tid;
    (void)send(waker->second, &message, sizeof message, MSG_NOSIGNAL | MSG_DONTWAIT);
    thread.blocked = false;
    thread.woken_by_us = true;   // it says RUNNING when it leaves the wait
    return true;
  }

  // When something was delivered, only the threads that wait on descriptors are told (they
  // look again); a sleep or a wait on an object whose deadline came at this instant is woken
  // in the next round, after the threads that got the delivery have settled. So two threads
  // woken at one instant — a reader that got bytes and a 10 ms timer — run one after the
  // other, in the same order every run, not in whatever order the machine schedules them.
  // Returns whether any thread was told (or is due and waits for its waker's hello).
  bool wake_due_and_poke(bool delivered) {
    const std::int64_t now = executor.now().count();
    bool told = false;
    // A thread the bytes already woke (on a shared CPU it runs at once) said RUNNING, and may
    // wait again by now: a poke would only wake it once more for nothing.
    if (delivered) pump(0);
    for (auto& [fd, thread] : threads) {
      if (!thread.blocked || thread.waker) continue;
      if (delivered) {
        if (thread.seq == thread.seq_at_flush && thread.wait != WaitKind::sleep && !waits_on_object(thread.wait)) {
          send_to(fd, thread, thread.deadline <= now ? ControlKind::wake : ControlKind::poke);
          told = true;
        }
      } else if (thread.deadline <= now) {
        if (!waits_on_object(thread.wait)) {
          send_to(fd, thread, ControlKind::wake);
        } else {
          wake_through_waker(thread);
        }
        told = true;
      }
    }
    return told;
  }

  std::int64_t earliest_deadline() const {
    std::int64_t earliest = no_deadline;
    for (const auto& [fd, thread] : threads) {
      if (thread.blocked) earliest = std::min(earliest, thread.deadline);
    }
    return earliest;
  }

  SimTime run_until(SimTime end, const std::function<bool()>& interrupted) {
    run_started = Clock::now();
    std::size_t rounds_here = 0;
    SimTime last_instant = executor.now();
    // Quiescence holds until we wake a thread or deliver something: an instant where the
    // simulator only ran its own events (a link delay, a camera frame) needs no new wait.
    bool stirred = true;
    while (true) {
      // Nor does it without a word from the clients: a message (a thread that woke by itself),
      // a connection that ended, a process still to greet or to be refused stirs it.
      if (!stirred) stirred = pump(0) || expecting_a_greeting() || !unclaimed.empty() || !unshimmed.empty();
      if (stirred) {
        const auto settling = Clock::now();
        settle();
        settle_wall += Clock::now() - settling;
        stats.settle_us = static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::microseconds>(settle_wall).count());
      }
      const bool took = take_from_clients();
      executor.run_until(executor.now());
      const bool delivered = flush_to_clients();
      if (delivered || took) {
        if ((rounds_here & 63) == 63) check_limits();
        if (++rounds_here > max_same_instant_rounds) {
          throw VirtualTimeError("the client and the simulator exchanged bytes " + std::to_string(max_same_instant_rounds) +
                                 " times without virtual time advancing");
        }
        stirred = wake_due_and_poke(delivered) || delivered;
        continue;
      }
      if (earliest_deadline() <= executor.now().count()) {   // a timer due now (armed at this instant)
        stirred = wake_due_and_poke(false);
        continue;
      }
      if (executor.now() >= end) break;
      if (interrupted && interrupted()) break;
      const SimTime next = std::max(executor.now(), std::min({executor.next_deadline(), SimTime{earliest_deadline()}, end}));
      page->now_us.store(next.count(), std::memory_order_release);
      executor.run_until(next);
      if (next != last_instant) {
        if ((++stats.instants & 255) == 0) check_limits();
        rounds_here = 0;
        last_instant = next;
      }
      const bool delivered_now = flush_to_clients();
      stirred = wake_due_and_poke(delivered_now) || delivered_now;
    }
    stats.run_us += static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - run_started).count());
    trace_line("run ended: " + std::to_string(stats.instants) + " instants, " + std::to_string(stats.settles) + " settles (" +
               std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(settle_wall).count()) + " ms), " +
               std::to_string(stats.proc_checks) + " /proc looks, " + std::to_string(stats.messages) + " messages, " +
               std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - run_started).count()) + " ms wall");
    return executor.now();
  }
  Clock::duration settle_wall{};
};

Controller::Controller(VirtualExecutor& executor, ControllerOptions options)
    : impl_(std::make_unique<Impl>(executor, std::move(options))), stats_(impl_->stats) {
  impl_->open();
}

Controller::~Controller() = default;

std::vector<std::string> Controller::environment() const {
  std::string preload = impl_->options.shim_path;
  if (const char* existing = std::getenv("LD_PRELOAD"); existing != nullptr && *existing != '\0') preload += std::string(":") + existing;
  // A client built with AddressSanitizer wants its runtime first among the preloaded
  // libraries; the shim comes first, and only wraps what ASan wraps too, so the check is off.
  std::string asan = "verify_asan_link_order=0";
  if (const char* existing = std::getenv("ASAN_OPTIONS"); existing != nullptr && *existing != '\0') asan = std::string(existing) + ":" + asan;
  return {"LD_PRELOAD=" + preload, std::string(socket_env) + "=" + impl_->socket_path,
          std::string(clock_env) + "=" + impl_->clock_path, "ASAN_OPTIONS=" + asan};
}

int Controller::listen(std::uint16_t port, AcceptHandler on_accept) {
  const int fd = impl_->open_listener(port);
  sockaddr_in bound{};
  socklen_t size = sizeof bound;
  getsockname(fd, reinterpret_cast<sockaddr*>(&bound), &size);
  impl_->listeners.push_back({fd, ntohs(bound.sin_port), std::move(on_accept)});
  return static_cast<int>(impl_->listeners.size() - 1);
}

std::uint16_t Controller::port(int listener) const { return impl_->listeners.at(static_cast<std::size_t>(listener)).port; }

void Controller::close_listener_for(int listener, Micros down) {
  Impl::Listener& entry = impl_->listeners.at(static_cast<std::size_t>(listener));
  if (entry.fd >= 0) ::close(entry.fd);
  entry.fd = -1;
  impl_->executor.call_after(down, [impl = impl_.get(), listener] {
    Impl::Listener& again = impl->listeners.at(static_cast<std::size_t>(listener));
    if (again.fd < 0) again.fd = impl->open_listener(again.port);
  });
}

void Controller::expect_process(pid_t pid, std::string name, std::function<bool()> alive) {
  impl_->expected.push_back({pid, std::move(name), std::move(alive), Clock::now(), false});
}

SimTime Controller::run_until(SimTime end, const std::function<bool()>& interrupted) { return impl_->run_until(end, interrupted); }

}  // namespace ocp::vtime
