#include "kernel_floor.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sched.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <chrono>
#include <cstring>
#include <thread>
#include <vector>

#include "blocking_socket.hpp"
#include "process_usage.hpp"

namespace ocp::bench {

namespace {

using Clock = std::chrono::steady_clock;

// Closes every descriptor it holds when it goes.
struct Sockets {
  std::vector<int> fds;
  ~Sockets() {
    for (const int fd : fds) close(fd);
  }
};

std::string system_error(const char* what) { return fmt::format("{}: {}", what, std::strerror(errno)); }

// A listening socket on 127.0.0.1, on a free port (written into `address`). Empty: no error.
std::string open_listener(Sockets& listener, sockaddr_in& address) {
  listener.fds.push_back(socket(AF_INET, SOCK_STREAM, 0));
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof address;
  const int listen_fd = listener.fds.front();
  if (listen_fd < 0 || bind(listen_fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 ||
      listen(listen_fd, 128) != 0 || getsockname(listen_fd, reinterpret_cast<sockaddr*>(&address), &length) != 0) {
    return system_error("listen");
  }
  return {};
}

// `connections` connected pairs: servers[i] is the Streamer's end of clients[i]. Empty: no error.
std::string connect_pairs(int listen_fd, std::uint16_t port, int connections, Sockets& servers, Sockets& clients) {
  const int one = 1;
  const timeval stuck{5, 0};   // a frame that has not arrived after this never will: an error, not a hang
  for (int index = 0; index < connections; ++index) {
    const int client = connect_loopback(port);
    if (client < 0) return system_error(fmt::format("connection {} of {}", index + 1, connections).c_str());
    clients.fds.push_back(client);
    const int server = accept(listen_fd, nullptr, nullptr);   // one at a time: the backlog never fills
    if (server < 0) return system_error(fmt::format("accept {} of {}", index + 1, connections).c_str());
    servers.fds.push_back(server);
    setsockopt(server, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);   // the client's end has it already
    for (const int fd : {client, server}) setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &stuck, sizeof stuck);
  }
  return {};
}

// One tick: every control frame out, every client answers, every response read back.
class EchoRound {
 public:
  EchoRound(const Sockets& servers, const Sockets& clients, std::size_t control_bytes, std::size_t response_bytes)
      : servers_(servers), clients_(clients), control_(control_bytes, 'c'), response_(response_bytes, 'r'),
        buffer_(std::max(control_bytes, response_bytes)) {}

  bool run() {
    for (const int server : servers_.fds) {
      if (!send_all(server, control_.data(), control_.size())) return false;
    }
    for (const int client : clients_.fds) {
      if (!receive_all(client, buffer_.data(), control_.size()) || !send_all(client, response_.data(), response_.size())) {
        return false;
      }
    }
    for (const int server : servers_.fds) {
      if (!receive_all(server, buffer_.data(), response_.size())) return false;
    }
    return true;
  }

 private:
  const Sockets& servers_;
  const Sockets& clients_;
  const std::vector<char> control_;
  const std::vector<char> response_;
  std::vector<char> buffer_;
};

// The per-tick figures from cpu_s and vehicle_ticks.
void fill_per_tick(KernelFloor& floor, int connections) {
  floor.us_per_vehicle_tick = floor.cpu_s * 1e6 / static_cast<double>(floor.vehicle_ticks);
  floor.cpu_per_s_at_100hz = floor.us_per_vehicle_tick * 1e-6 * connections * 100.0;
  floor.ok = true;
}

// Three unmeasured rounds, then rounds for `duration_s` (at least three), on this thread's CPU clock.
void measure_rounds(EchoRound& round, int connections, double duration_s, KernelFloor& floor) {
  for (int warm_up = 0; warm_up < 3; ++warm_up) {
    if (!round.run()) {
      floor.error = system_error("warm-up round");
      return;
    }
  }
  const double cpu_start = thread_cpu_seconds();
  const auto wall_start = Clock::now();
  const auto end = wall_start + std::chrono::duration<double>(duration_s);
  std::uint64_t rounds = 0;
  while (rounds < 3 || Clock::now() < end) {
    if (!round.run()) {
      floor.error = system_error("round");
      return;
    }
    ++rounds;
  }
  floor.cpu_s = thread_cpu_seconds() - cpu_start;
  floor.wall_s = std::chrono::duration<double>(Clock::now() - wall_start).count();
  floor.vehicle_ticks = rounds * static_cast<std::uint64_t>(connections);
  fill_per_tick(floor, connections);
}

// The paced floor's part for one server thread: its connections [first, last) and its phase.
struct PacedPart {
  int first = 0;
  int last = 0;
  Clock::duration phase{};
};

// What one thread of the paced floor measured.
struct PacedOutcome {
  double cpu_s = 0;
  double wall_s = 0;  // from the first measured period's start to the last thread's end
  std::string error;
};

constexpr Clock::duration paced_period = std::chrono::milliseconds(10);
constexpr int paced_warm_up_periods = 2;

class PacedFloor {
 public:
  PacedFloor(const PacedShape& shape, const Sockets& servers, const Sockets& clients, std::size_t control_bytes,
             std::size_t response_bytes, int measured_periods)
      : shape_(shape),
        servers_(servers),
        clients_(clients),
        control_(control_bytes, 'c'),
        response_(response_bytes, 'r'),
        periods_(paced_warm_up_periods + measured_periods) {}

  // Every thread's CPU over the measured periods, summed, and their wall time; empty error: all
  // went well.
  PacedOutcome run() {
    const int threads = shape_.server_threads;
    const Clock::duration slot_step = paced_period / shape_.slots;
    std::vector<PacedPart> parts;
    for (int index = 0; index < threads; ++index) {
      parts.push_back({shape_.connections * index / threads, shape_.connections * (index + 1) / threads,
                       slot_step * index / threads});
    }
    std::vector<PacedOutcome> outcomes(parts.size() * 2);
    start_ = Clock::now() + std::chrono::milliseconds(20);  // every thread created before the first burst
    {
      std::vector<std::jthread> running;
      for (std::size_t index = 0; index < parts.size(); ++index) {
        running.emplace_back([this, &parts, &outcomes, index] { serve(parts[index], outcomes[index]); });
        if (shape_.client_threads_of_their_own) {
          running.emplace_back(
              [this, &parts, &outcomes, index] { answer(parts[index], outcomes[parts.size() + index]); });
        }
      }
    }
    PacedOutcome total;
    total.wall_s =
        std::chrono::duration<double>(Clock::now() - (start_ + paced_period * paced_warm_up_periods)).count();
    for (const auto& outcome : outcomes) {
      total.cpu_s += outcome.cpu_s;
      if (total.error.empty()) total.error = outcome.error;
    }
    return total;
  }

 private:
  void serve(const PacedPart& part, PacedOutcome& outcome) {
    std::vector<char> buffer(std::max(control_.size(), response_.size()));
    const int count = part.last - part.first;
    double cpu_start = 0;
    for (int period = 0; period < periods_ && outcome.error.empty(); ++period) {
      if (period == paced_warm_up_periods) cpu_start = thread_cpu_seconds();
      for (int slot = 0; slot < shape_.slots && outcome.error.empty(); ++slot) {
        std::this_thread::sleep_until(start_ + part.phase + paced_period * period + paced_period / shape_.slots * slot);
        const int first = part.first + count * slot / shape_.slots;
        const int last = part.first + count * (slot + 1) / shape_.slots;
        if (!burst(first, last, buffer)) outcome.error = system_error("paced round");
      }
    }
    if (outcome.error.empty()) outcome.cpu_s = thread_cpu_seconds() - cpu_start;
    // The client thread's next read meets the end of the stream and stops.
    for (int index = part.first; index < part.last; ++index) shutdown(servers_.fds[index], SHUT_WR);
  }

  // One slot's frames out, answered (here, unless a client thread does it), and read back.
  bool burst(int first, int last, std::vector<char>& buffer) {
    for (int index = first; index < last; ++index) {
      if (!send_all(servers_.fds[index], control_.data(), control_.size())) return false;
    }
    if (!shape_.client_threads_of_their_own) {
      for (int index = first; index < last; ++index) {
        if (!answer_one(index, buffer)) return false;
      }
    }
    for (int index = first; index < last; ++index) {
      if (!receive_all(servers_.fds[index], buffer.data(), response_.size())) return false;
    }
    return true;
  }

  bool answer_one(int index, std::vector<char>& buffer) {
    return receive_all(clients_.fds[index], buffer.data(), control_.size()) &&
           send_all(clients_.fds[index], response_.data(), response_.size());
  }

  // The frames come in connection order, period after period, so a blocking read of each
  // connection in turn is always the next one due.
  void answer(const PacedPart& part, PacedOutcome& outcome) {
    std::vector<char> buffer(std::max(control_.size(), response_.size()));
    const int count = part.last - part.first;
    double cpu_start = thread_cpu_seconds();
    for (int period = 0; period < periods_; ++period) {
      if (period == paced_warm_up_periods) cpu_start = thread_cpu_seconds();
      for (int index = part.first; index < part.last; ++index) {
        if (!answer_one(index, buffer)) {
          outcome.error = system_error(
              fmt::format("paced answer {} of {}", period * count + index - part.first + 1, periods_ * count).c_str());
          return;
        }
      }
    }
    outcome.cpu_s = thread_cpu_seconds() - cpu_start;
  }

  const PacedShape shape_;
  const Sockets& servers_;
  const Sockets& clients_;
  const std::string control_;
  const std::string response_;
  const int periods_;
  Clock::time_point start_{};
};

// A listener and `connections` connected pairs. Empty: no error.
std::string open_pairs(int connections, Sockets& servers, Sockets& clients) {
  make_room_for_descriptors(2 * static_cast<std::size_t>(connections) + 1);
  Sockets listener;
  sockaddr_in address{};
  std::string error = open_listener(listener, address);
  if (error.empty()) {
    error = connect_pairs(listener.fds.front(), ntohs(address.sin_port), connections, servers, clients);
  }
  return error;
}

}  // namespace

KernelFloor measure_kernel_floor(int connections, std::size_t control_bytes, std::size_t response_bytes,
                                 double duration_s) {
  KernelFloor floor;
  if (connections <= 0 || control_bytes == 0 || response_bytes == 0) {
    floor.error = "nothing to measure";
    return floor;
  }
  Sockets servers, clients;
  floor.error = open_pairs(connections, servers, clients);
  if (!floor.error.empty()) return floor;
  EchoRound round(servers, clients, control_bytes, response_bytes);
  measure_rounds(round, connections, duration_s, floor);
  return floor;
}

KernelFloor measure_paced_kernel_floor(const PacedShape& shape, std::size_t control_bytes, std::size_t response_bytes,
                                       double duration_s) {
  KernelFloor floor;
  if (shape.connections <= 0 || shape.server_threads <= 0 || shape.slots <= 0 || control_bytes == 0 ||
      response_bytes == 0) {
    floor.error = "nothing to measure";
    return floor;
  }
  if (shape.server_threads > shape.connections) {
    floor.error = "more server threads than connections";
    return floor;
  }
  Sockets servers, clients;
  floor.error = open_pairs(shape.connections, servers, clients);
  if (!floor.error.empty()) return floor;
  const int periods =
      std::max(3, static_cast<int>(std::lround(duration_s / std::chrono::duration<double>(paced_period).count())));
  PacedOutcome outcome = PacedFloor(shape, servers, clients, control_bytes, response_bytes, periods).run();
  if (!outcome.error.empty()) {
    floor.error = std::move(outcome.error);
    return floor;
  }
  floor.cpu_s = outcome.cpu_s;
  floor.wall_s = outcome.wall_s;
  floor.vehicle_ticks = static_cast<std::uint64_t>(periods) * static_cast<std::uint64_t>(shape.connections);
  fill_per_tick(floor, shape.connections);
  return floor;
}

int usable_cores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0 && CPU_COUNT(&set) > 0) return CPU_COUNT(&set);
  return static_cast<int>(std::max(1U, std::thread::hardware_concurrency()));
}

}  // namespace ocp::bench
