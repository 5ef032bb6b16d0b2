#pragma once
// Real-time TCP side of the vehicle client: connects to host:port with Boost.Asio, hands the
// connected socket (TCP_NODELAY) to VehicleClient::attach via make_tcp_stream, and reconnects
// after a short, growing backoff whenever the connection cannot be made or drops. Every
// outcome is reported in plain words: refused, timed out, not an OCP server, disconnected.
#include <boost/asio/ip/tcp.hpp>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

#include "ocp/asio/executor.hpp"
#include "ocp/error.hpp"
#include "ocp/log.hpp"
#include "vehicle_client/vehicle_client.hpp"

namespace ocp {

struct Endpoint {
  std::string host = "127.0.0.1";
  std::uint16_t port = 4000;
  std::string to_string() const { return host + ":" + std::to_string(port); }
};
// "host:port", "host" (default port), ":port" or "[v6addr]:port". Bad input → error text.
Result<Endpoint> parse_endpoint(std::string_view text, std::uint16_t default_port = 4000);

struct TcpRunnerConfig {
  Endpoint server;
  Micros connect_timeout{2'000'000};
  Micros backoff_initial{100'000};  // first retry delay; doubles per failure up to max
  Micros backoff_max{2'000'000};
  bool reconnect = true;            // false: stop after the first connection ends or fails
};

enum class ConnectionEventKind : std::uint8_t {
  connecting,         // an attempt started
  connected,          // socket up, client attached
  refused,            // nothing listening (ECONNREFUSED)
  timed_out,          // no answer within connect_timeout
  failed,             // resolve error or other socket error
  not_an_ocp_server,  // connected, but the peer spoke something else (see DisconnectKind)
  disconnected,       // an established OCP connection ended
  retry_scheduled,    // next attempt after `retry_in`
  stopped,            // stop() called or reconnect disabled
};
std::string_view connection_event_name(ConnectionEventKind kind);

struct RunnerConnectionEvent {
  ConnectionEventKind kind;
  std::string detail;   // human-readable, ready to print
  Micros retry_in{0};   // for retry_scheduled
};

struct TcpRunnerStats {
  std::uint64_t attempts = 0;
  std::uint64_t connections = 0;
  std::uint64_t refused = 0;
  std::uint64_t timed_out = 0;
  std::uint64_t failed = 0;
  std::uint64_t not_an_ocp_server = 0;
  std::uint64_t disconnects = 0;
};

class TcpRunner {
 public:
  TcpRunner(AsioExecutor& executor, VehicleClient& client, TcpRunnerConfig config, Logger logger);
  ~TcpRunner();
  TcpRunner(const TcpRunner&) = delete;
  TcpRunner& operator=(const TcpRunner&) = delete;

  // Starts the first attempt; everything else happens as the io_context runs.
  void start();
  // Cancels any attempt or retry and detaches the client. Safe to call twice.
  void stop();
  bool running() const { return running_; }
  void set_on_event(std::function<void(const RunnerConnectionEvent&)> callback);
  const TcpRunnerStats& stats() const { return stats_; }
  Micros current_backoff() const { return backoff_; }

 private:
  struct Attempt;
  void connect();
  void on_connected(const std::shared_ptr<Attempt>& attempt);
  void on_attempt_failed(ConnectionEventKind kind, const std::string& detail);
  void on_client_disconnected(const std::string& reason);
  void schedule_retry();
  void emit(ConnectionEventKind kind, std::string detail, Micros retry_in = Micros{0});

  AsioExecutor& executor_;
  VehicleClient& client_;
  TcpRunnerConfig config_;
  Logger logger_;
  TcpRunnerStats stats_;
  std::function<void(const RunnerConnectionEvent&)> on_event_;
  std::shared_ptr<Attempt> attempt_;
  Executor::TimerId retry_timer_ = 0;
  Micros backoff_;
  bool running_ = false;
  std::uint64_t control_seen_at_connect_ = 0;
  LivenessToken liveness_;  // async handlers watch it: no-ops once this is destroyed
};

}  // namespace ocp
