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
  floor.us_per_vehicle_tick = floor.cpu_s * 1e6 / static_cast<double>(floor.vehicle_ticks);
  floor.cpu_per_s_at_100hz = floor.us_per_vehicle_tick * 1e-6 * connections * 100.0;
  floor.ok = true;
}

}  // namespace

KernelFloor measure_kernel_floor(int connections, std::size_t control_bytes, std::size_t response_bytes,
                                 double duration_s) {
  KernelFloor floor;
  if (connections <= 0 || control_bytes == 0 || response_bytes == 0) {
    floor.error = "nothing to measure";
    return floor;
  }
  make_room_for_descriptors(2 * static_cast<std::size_t>(connections) + 1);
  Sockets listener, servers, clients;
  sockaddr_in address{};
  floor.error = open_listener(listener, address);
  if (floor.error.empty()) {
    floor.error = connect_pairs(listener.fds.front(), ntohs(address.sin_port), connections, servers, clients);
  }
  if (!floor.error.empty()) return floor;
  EchoRound round(servers, clients, control_bytes, response_bytes);
  measure_rounds(round, connections, duration_s, floor);
  return floor;
}

int usable_cores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0 && CPU_COUNT(&set) > 0) return CPU_COUNT(&set);
  return static_cast<int>(std::max(1U, std::thread::hardware_concurrency()));
}

}  // namespace ocp::bench
