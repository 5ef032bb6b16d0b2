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

#include "controller_impl.hpp"
#include "vtime/protocol.hpp"

namespace ocp::vtime {

namespace {

std::string errno_text() { return std::strerror(errno); }

}  // namespace

void Controller::Impl::open() {
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

Controller::Impl::~Impl() {
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

void Controller::Impl::trace_line(const std::string& text) {
  if (!trace.is_open()) return;
  trace << executor.now().count() << " µs: " << text << '\n';
}

int Controller::Impl::open_listener(std::uint16_t port) {
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

void Controller::Impl::accept_threads() {
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

void Controller::Impl::forget_thread(int fd) {
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

void Controller::Impl::on_message(int fd, ThreadRecord& thread, const ShimMessage& message) {
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
      thread.on_object = message.on_object;
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
bool Controller::Impl::pump(int wait_ms) {
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

void Controller::Impl::read_messages(int fd) {
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

// Every connection a client made at this instant (the shim announced it: the kernel may not
// have queued it yet under load, so wait for it, bounded).
void Controller::Impl::accept_connections() {
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

void Controller::Impl::accept_queued() {
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
bool Controller::Impl::take_from_clients() {
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
bool Controller::Impl::flush_to_clients() {
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

void Controller::Impl::send_to(int fd, ThreadRecord& thread, ControlKind kind) {
  ControlMessage message{};
  message.kind = kind;
  message.seq = thread.seq;
  (void)send(fd, &message, sizeof message, MSG_NOSIGNAL | MSG_DONTWAIT);
  thread.blocked = false;
  thread.woken_by_us = true;
}

// A wait on an object ends through the process's waker, which wakes the object for real.
// False when the waker has not said hello yet (the next round tries again).
bool Controller::Impl::wake_through_waker(ThreadRecord& thread) {
  const auto waker = wakers.find(thread.pid);
  if (waker == wakers.end()) return false;
  ControlMessage message{};
  message.kind = ControlKind::wake;
  message.seq = thread.seq;
  message.wait = thread.wait;
  message.tid = thread.tid;
  message.on_object = thread.on_object;
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
bool Controller::Impl::wake_due_and_poke(bool delivered) {
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

std::int64_t Controller::Impl::earliest_deadline() const {
  std::int64_t earliest = no_deadline;
  for (const auto& [fd, thread] : threads) {
    if (thread.blocked) earliest = std::min(earliest, thread.deadline);
  }
  return earliest;
}

SimTime Controller::Impl::run_until(SimTime end, const std::function<bool()>& interrupted) {
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
  impl_->expected.push_back({pid, std::move(name), std::move(alive), Impl::Clock::now(), false});
}

SimTime Controller::run_until(SimTime end, const std::function<bool()>& interrupted) { return impl_->run_until(end, interrupted); }

}  // namespace ocp::vtime
