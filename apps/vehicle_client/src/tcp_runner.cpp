#include "vehicle_app/tcp_runner.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <boost/asio/connect.hpp>
#include <boost/asio/error.hpp>
#include <charconv>

#include "ocp/asio/tcp_stream.hpp"

namespace ocp {

namespace asio = boost::asio;
using asio::ip::tcp;

std::string_view connection_event_name(ConnectionEventKind kind) {
  switch (kind) {
    case ConnectionEventKind::connecting: return "connecting";
    case ConnectionEventKind::connected: return "connected";
    case ConnectionEventKind::refused: return "refused";
    case ConnectionEventKind::timed_out: return "timed_out";
    case ConnectionEventKind::failed: return "failed";
    case ConnectionEventKind::not_an_ocp_server: return "not_an_ocp_server";
    case ConnectionEventKind::disconnected: return "disconnected";
    case ConnectionEventKind::retry_scheduled: return "retry_scheduled";
    case ConnectionEventKind::stopped: return "stopped";
  }
  return "unknown";
}

Result<Endpoint> parse_endpoint(std::string_view text, std::uint16_t default_port) {
  const auto bad = [text](std::string_view why) {
    return Error{std::make_error_code(std::errc::invalid_argument),
                 fmt::format("\"{}\": {} (expected host:port, e.g. 127.0.0.1:4000)", text, why)};
  };
  Endpoint endpoint;
  endpoint.port = default_port;
  std::string_view host = text;
  std::string_view port_text;
  if (text.starts_with('[')) {  // [v6]:port
    const auto close = text.find(']');
    if (close == std::string_view::npos) return bad("missing ']'");
    host = text.substr(1, close - 1);
    const std::string_view rest = text.substr(close + 1);
    if (!rest.empty()) {
      if (!rest.starts_with(':')) return bad("expected ':' after ']'");
      port_text = rest.substr(1);
      if (port_text.empty()) return bad("empty port");
    }
  } else if (const auto colon = text.rfind(':'); colon != std::string_view::npos) {
    if (text.find(':') != colon) return bad("IPv6 addresses need brackets: [addr]:port");
    host = text.substr(0, colon);
    port_text = text.substr(colon + 1);
    if (port_text.empty()) return bad("empty port");
  }
  if (!port_text.empty()) {
    unsigned port = 0;
    const auto [end, error] = std::from_chars(port_text.data(), port_text.data() + port_text.size(), port);
    if (error != std::errc{} || end != port_text.data() + port_text.size() || port == 0 || port > 65535) {
      return bad("port must be a number in 1..65535");
    }
    endpoint.port = static_cast<std::uint16_t>(port);
  }
  if (!host.empty()) endpoint.host = std::string(host);
  return endpoint;
}

struct TcpRunner::Attempt {
  explicit Attempt(asio::io_context& io) : resolver(io), socket(io) {}
  tcp::resolver resolver;
  tcp::socket socket;
  Executor::TimerId timeout_timer = 0;
  bool finished = false;
  bool timed_out = false;
};

TcpRunner::TcpRunner(AsioExecutor& executor, VehicleClient& client, TcpRunnerConfig config, Logger logger)
    : executor_(executor),
      client_(client),
      config_(std::move(config)),
      logger_(std::move(logger)),
      backoff_(config_.backoff_initial) {
  const LivenessToken::Watch owner = liveness_.watch();
  client_.set_on_disconnected([this, owner](const std::string& reason) {
    if (owner.alive()) on_client_disconnected(reason);
  });
}

TcpRunner::~TcpRunner() {
  stop();
  liveness_.revoke();
  client_.set_on_disconnected(nullptr);
}

void TcpRunner::set_on_event(std::function<void(const RunnerConnectionEvent&)> callback) {
  on_event_ = std::move(callback);
}

void TcpRunner::emit(ConnectionEventKind kind, std::string detail, Micros retry_in) {
  switch (kind) {
    case ConnectionEventKind::connected:
    case ConnectionEventKind::connecting:
    case ConnectionEventKind::stopped: logger_.info("{}", detail); break;
    case ConnectionEventKind::retry_scheduled: logger_.debug("{}", detail); break;
    default: logger_.warn("{}", detail); break;
  }
  if (on_event_) on_event_(RunnerConnectionEvent{kind, std::move(detail), retry_in});
}

void TcpRunner::start() {
  if (running_) return;
  running_ = true;
  backoff_ = config_.backoff_initial;
  connect();
}

void TcpRunner::stop() {
  if (!running_) return;
  running_ = false;
  if (retry_timer_ != 0) executor_.cancel(retry_timer_);
  retry_timer_ = 0;
  if (attempt_) {
    attempt_->finished = true;
    if (attempt_->timeout_timer != 0) executor_.cancel(attempt_->timeout_timer);
    attempt_->resolver.cancel();
    boost::system::error_code ignored;
    attempt_->socket.close(ignored);
    attempt_.reset();
  }
  client_.detach();
  emit(ConnectionEventKind::stopped, "stopped");
}

void TcpRunner::connect() {
  retry_timer_ = 0;
  if (!running_) return;
  ++stats_.attempts;
  auto attempt = std::make_shared<Attempt>(executor_.io());
  attempt_ = attempt;
  emit(ConnectionEventKind::connecting, fmt::format("connecting to {}", config_.server.to_string()));

  const LivenessToken::Watch owner = liveness_.watch();
  attempt->timeout_timer = executor_.call_after(config_.connect_timeout, [attempt] {
    if (attempt->finished) return;
    attempt->timeout_timer = 0;
    attempt->timed_out = true;
    attempt->resolver.cancel();
    boost::system::error_code ignored;
    attempt->socket.close(ignored);  // completes the pending connect with operation_aborted
  });

  const auto on_connect = [this, owner, attempt](const boost::system::error_code& error, const tcp::endpoint&) {
    if (!owner.alive() || attempt->finished) return;
    const std::string server = config_.server.to_string();
    if (attempt->timed_out) {
      on_attempt_failed(ConnectionEventKind::timed_out,
                        fmt::format("connect to {} timed out after {} ms", server,
                                    to_whole_ms(config_.connect_timeout)));
    } else if (error == asio::error::connection_refused) {
      on_attempt_failed(ConnectionEventKind::refused,
                        fmt::format("connection to {} refused: is the Streamer running and tcp_port right?",
                                    server));
    } else if (error) {
      on_attempt_failed(ConnectionEventKind::failed,
                        fmt::format("cannot connect to {}: {}", server, error.message()));
    } else {
      on_connected(attempt);
    }
  };
  attempt->resolver.async_resolve(
      config_.server.host, std::to_string(config_.server.port),
      [this, owner, attempt, on_connect](const boost::system::error_code& error,
                                         const tcp::resolver::results_type& results) {
        if (!owner.alive() || attempt->finished) return;
        if (attempt->timed_out) {
          on_connect(asio::error::timed_out, tcp::endpoint{});
        } else if (error) {
          on_attempt_failed(ConnectionEventKind::failed,
                            fmt::format("cannot resolve {}: {}", config_.server.host, error.message()));
        } else {
          asio::async_connect(attempt->socket, results, on_connect);
        }
      });
}

void TcpRunner::on_connected(const std::shared_ptr<Attempt>& attempt) {
  attempt->finished = true;
  if (attempt->timeout_timer != 0) executor_.cancel(attempt->timeout_timer);
  attempt_.reset();
  ++stats_.connections;
  control_seen_at_connect_ = client_.stats().control_messages_received;
  std::shared_ptr<ByteStream> stream = make_tcp_stream(std::move(attempt->socket));
  emit(ConnectionEventKind::connected, fmt::format("connected to {}", config_.server.to_string()));
  client_.attach(std::move(stream));
}

void TcpRunner::on_attempt_failed(ConnectionEventKind kind, const std::string& detail) {
  if (attempt_) {
    attempt_->finished = true;
    if (attempt_->timeout_timer != 0) executor_.cancel(attempt_->timeout_timer);
    attempt_.reset();
  }
  if (kind == ConnectionEventKind::refused) ++stats_.refused;
  if (kind == ConnectionEventKind::timed_out) ++stats_.timed_out;
  if (kind == ConnectionEventKind::failed) ++stats_.failed;
  emit(kind, detail);
  schedule_retry();
}

void TcpRunner::on_client_disconnected(const std::string& reason) {
  if (client_.stats().last_disconnect_kind == DisconnectKind::not_an_ocp_server) {
    ++stats_.not_an_ocp_server;
    emit(ConnectionEventKind::not_an_ocp_server, fmt::format("{}: {}", config_.server.to_string(), reason));
  } else {
    ++stats_.disconnects;
    emit(ConnectionEventKind::disconnected, fmt::format("connection to {} ended: {}", config_.server.to_string(), reason));
    // A session that carried control messages worked: the next attempt may be quick again.
    if (client_.stats().control_messages_received > control_seen_at_connect_) backoff_ = config_.backoff_initial;
  }
  schedule_retry();
}

void TcpRunner::schedule_retry() {
  if (!running_) return;
  if (!config_.reconnect) {
    running_ = false;
    emit(ConnectionEventKind::stopped, "not reconnecting (reconnect disabled)");
    return;
  }
  const Micros delay = backoff_;
  backoff_ = std::min(backoff_ * 2, config_.backoff_max);
  emit(ConnectionEventKind::retry_scheduled, fmt::format("retrying in {} ms", to_whole_ms(delay)), delay);
  const LivenessToken::Watch owner = liveness_.watch();
  retry_timer_ = executor_.call_after(delay, [this, owner] {
    if (owner.alive()) connect();
  });
}

}  // namespace ocp
