#pragma once
// The Controller's state (controller.hpp), shared by its two halves: controller.cpp has the
// setup, the shims' messages, the OCP connections, the waking and the loop; quiescence.cpp the
// wait for quiescence, the /proc looks and the limits (busy loop, hang, no shim).
#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "clock_page.hpp"
#include "cpu_pin.hpp"
#include "proc_scan.hpp"
#include "socket_stream.hpp"
#include "vtime/controller.hpp"
#include "vtime/protocol.hpp"

namespace ocp::vtime {

struct Controller::Impl {
  using Clock = std::chrono::steady_clock;
  static constexpr std::size_t max_threads = 1024;   // client threads tracked, all processes
  static constexpr std::size_t max_processes = 64;
  static constexpr std::size_t max_same_instant_rounds = 100'000;

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
    ObjectWait on_object{};        // a wait on an object: as its BLOCKED said
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

  Clock::duration settle_wall{};   // waiting for quiescence, for the stats
  ~Impl();

  // ------------------------------------------------------------ setup
  void open();
  void trace_line(const std::string& text);
  int open_listener(std::uint16_t port);

  // ------------------------------------------------------------ messages from the shims
  void accept_threads();
  void forget_thread(int fd);
  void on_message(int fd, ThreadRecord& thread, const ShimMessage& message);
  bool pump(int wait_ms);
  void read_messages(int fd);

  // ------------------------------------------------------------ quiescence
  bool all_blocked_by_record() const;
  bool none_woken_silent() const;
  std::vector<pid_t> watched_pids();
  void check_unshimmed();
  bool runnable(pid_t pid);
  bool asleep_in_proc();
  bool asleep_in_proc_now();
  std::optional<bool> single_look();
  bool pinned_here(pid_t tid);
  static long own_switches();
  std::string waiting_for();
  std::string awake_description();
  std::uint64_t client_cpu();
  void check_limits();
  void check_busy(Clock::time_point settle_began, std::optional<std::uint64_t>& cpu_at_start);
  bool starting_up();
  bool unshimmed_alive();
  bool expecting_a_greeting() const;
  void settle();

  // ------------------------------------------------------------ the OCP connections
  void accept_connections();
  void accept_queued();
  bool take_from_clients();
  bool flush_to_clients();

  // ------------------------------------------------------------ waking
  void send_to(int fd, ThreadRecord& thread, ControlKind kind);
  bool wake_through_waker(ThreadRecord& thread);
  bool wake_due_and_poke(bool delivered);
  std::int64_t earliest_deadline() const;
  SimTime run_until(SimTime end, const std::function<bool()>& interrupted);
};

}  // namespace ocp::vtime
