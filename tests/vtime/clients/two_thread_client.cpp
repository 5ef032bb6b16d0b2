// A vehicle client shaped as many vendor examples are (docs/virtual-time.md, "Which clients
// work"): a reader thread that blocks in recv() on the Streamer's connection and answers each
// control message at once, and a timer thread that wakes every 10 ms and repeats the latest
// pair as a keep-alive when nothing was sent for 10 ms. They share the pair under a std::mutex.
//
//     two_thread_client [--cv] HOST:PORT
//
// The timer sleeps with std::this_thread::sleep_for (nanosleep), or with --cv in
// std::condition_variable::wait_for (pthread_cond_clockwait). The main thread is the reader;
// it reconnects when the connection ends. Written for the virtual-time tests; standard
// library and POSIX sockets only.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <string>
#include <thread>

namespace {

using Clock = std::chrono::steady_clock;
constexpr auto response_period = std::chrono::milliseconds(10);
constexpr std::uint32_t max_payload = 16384;

struct Shared {
  std::mutex mutex;
  std::condition_variable tick;   // --cv: the timer waits on it
  int fd = -1;                    // -1: not connected
  std::string pair;               // "ack_time":…,"ack_time_mac":… as they came; empty: none yet
  std::uint64_t received = 0;
  Clock::time_point last_sent;
};

// The raw text of the top-level members ack_time and ack_time_mac (a nested one is skipped).
std::string top_level_pair(const std::string& json) {
  std::string time_value, mac_value;
  int depth = 0;
  for (std::size_t i = 0; i < json.size(); ++i) {
    const char c = json[i];
    if (c == '{' || c == '[') ++depth;
    if (c == '}' || c == ']') --depth;
    if (c != '"') continue;
    const std::size_t end = json.find('"', i + 1);   // keys hold no escapes here
    if (end == std::string::npos) break;
    const std::string key = json.substr(i + 1, end - i - 1);
    std::size_t at = end + 1;
    while (at < json.size() && json[at] == ' ') ++at;
    if (depth == 1 && at < json.size() && json[at] == ':' && (key == "ack_time" || key == "ack_time_mac")) {
      std::size_t value_end = at + 1;
      if (json[value_end] == '"') value_end = json.find('"', value_end + 1) + 1;
      while (value_end < json.size() && json[value_end] != ',' && json[value_end] != '}') ++value_end;
      (key == "ack_time" ? time_value : mac_value) = json.substr(at + 1, value_end - at - 1);
    }
    i = end;   // past the string (a key, or a string value)
  }
  if (time_value.empty() || mac_value.empty()) return "";
  return "\"ack_time\":" + time_value + ",\"ack_time_mac\":" + mac_value;
}

// With the mutex held.
void send_response(Shared& shared) {
  const std::string json = "{" + shared.pair + ",\"vehicle_user_data\":{\"pos\":null,\"user_data\":{\"messages_received\":" +
                           std::to_string(shared.received) + "}}}";
  const std::uint32_t length = static_cast<std::uint32_t>(json.size());
  std::string frame(4, '\0');
  for (int i = 0; i < 4; ++i) frame[static_cast<std::size_t>(i)] = static_cast<char>((length >> (8 * i)) & 0xff);
  frame += json;
  for (std::size_t sent = 0; sent < frame.size();) {
    const ssize_t wrote = send(shared.fd, frame.data() + sent, frame.size() - sent, MSG_NOSIGNAL);
    if (wrote <= 0) return;   // the reader sees the end
    sent += static_cast<std::size_t>(wrote);
  }
  shared.last_sent = Clock::now();
}

void timer(Shared& shared, bool use_condition_variable) {
  for (;;) {
    std::unique_lock lock(shared.mutex, std::defer_lock);
    if (use_condition_variable) {
      lock.lock();
      shared.tick.wait_for(lock, response_period);
    } else {
      std::this_thread::sleep_for(response_period);
      lock.lock();
    }
    if (shared.fd >= 0 && !shared.pair.empty() && Clock::now() - shared.last_sent >= response_period) send_response(shared);
  }
}

// Reads frames until the connection ends; answers each control message at once.
void read_session(Shared& shared, int fd) {
  std::string buffer;
  char chunk[65536];
  for (;;) {
    const ssize_t got = recv(fd, chunk, sizeof chunk, 0);
    if (got <= 0) return;
    buffer.append(chunk, static_cast<std::size_t>(got));
    while (buffer.size() >= 4) {
      std::uint32_t length = 0;
      for (int i = 3; i >= 0; --i) length = (length << 8) | static_cast<unsigned char>(buffer[static_cast<std::size_t>(i)]);
      if (length > max_payload) return;   // not the Streamer
      if (buffer.size() < 4 + length) break;
      const std::string pair = top_level_pair(buffer.substr(4, length));
      buffer.erase(0, 4 + length);
      if (pair.empty()) continue;
      std::lock_guard lock(shared.mutex);
      shared.pair = pair;
      ++shared.received;
      send_response(shared);
    }
  }
}

int connect_to(const std::string& host, int port) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<std::uint16_t>(port));
  if (fd < 0 || inet_pton(AF_INET, host.c_str(), &address.sin_addr) != 1 ||
      connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    if (fd >= 0) close(fd);
    return -1;
  }
  const int yes = 1;
  setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);
  return fd;
}

}  // namespace

constexpr const char* usage =
    "usage: two_thread_client [--cv] HOST:PORT\n"
    "  a reader thread in recv and a 10 ms timer thread (sleep_for, or with --cv a condition wait)\n";

int main(int argc, char** argv) {
  if (argc == 2 && (std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0)) {
    std::fputs(usage, stdout);
    return 0;
  }
  bool use_condition_variable = false;
  std::string where;
  for (int i = 1; i < argc; ++i) {
    const std::string argument = argv[i];
    if (argument == "--cv") {
      use_condition_variable = true;
    } else if (argument.starts_with('-')) {
      std::fprintf(stderr, "two_thread_client: unknown option %s\n%s", argv[i], usage);
      return 2;
    } else if (where.empty()) {
      where = argument;
    } else {
      std::fprintf(stderr, "two_thread_client: more than one HOST:PORT (%s)\n%s", argv[i], usage);
      return 2;
    }
  }
  const auto colon = where.rfind(':');
  const int port = colon == std::string::npos ? 0 : std::atoi(where.c_str() + colon + 1);
  if (port < 1 || port > 65535) {
    std::fprintf(stderr, "two_thread_client: expected HOST:PORT with a port in 1..65535, got '%s'\n%s", where.c_str(), usage);
    return 2;
  }
  Shared shared;
  std::thread(timer, std::ref(shared), use_condition_variable).detach();
  auto backoff = std::chrono::milliseconds(100);
  for (;;) {
    const int fd = connect_to(where.substr(0, colon), port);
    if (fd >= 0) {
      std::fprintf(stderr, "connected to %s\n", where.c_str());
      backoff = std::chrono::milliseconds(100);
      {
        std::lock_guard lock(shared.mutex);
        shared.fd = fd;
        shared.pair.clear();
        shared.last_sent = Clock::now();
      }
      read_session(shared, fd);
      std::lock_guard lock(shared.mutex);
      shared.fd = -1;
      close(fd);
    }
    std::fprintf(stderr, "disconnected; reconnecting in %lld ms\n", static_cast<long long>(backoff.count()));
    std::this_thread::sleep_for(backoff);
    backoff = std::min(backoff * 2, std::chrono::milliseconds(2000));
  }
}
