#include "ocp/asio/tcp_server.hpp"

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <utility>

#include "ocp/asio/tcp_stream.hpp"

namespace ocp {

namespace {

using boost::asio::ip::tcp;

// How long to wait before accepting again after a transient accept failure (for example
// EMFILE): long enough not to spin, short enough that the next client barely notices.
constexpr std::chrono::milliseconds accept_retry_delay{100};

Error bind_error(std::errc code, std::string detail) {
  return Error{std::make_error_code(code), std::move(detail)};
}

// The code says "Address already in use"; the detail says where and why, without repeating
// it (Error::message() is "<code>: <detail>"; the executables print the detail alone).
Error address_in_use(const std::string& address) {
  return bind_error(std::errc::address_in_use, "another socket listens on " + address);
}

Error system_error(const boost::system::error_code& error, std::string detail) {
  return Error{std::error_code(error.value(), std::system_category()),
               std::move(detail) + ": " + error.message()};
}

}  // namespace

std::string listen_address(const TcpServerOptions& options) {
  return std::string(options.allow_remote ? "0.0.0.0" : "127.0.0.1") + ":" +
         std::to_string(options.port);
}

struct TcpServer::State : std::enable_shared_from_this<TcpServer::State> {
  explicit State(boost::asio::io_context& io) : acceptor(io), retry_timer(io) {}

  void accept_next() {
    acceptor.async_accept([self = shared_from_this()](const boost::system::error_code& error,
                                                      tcp::socket socket) {
      self->on_accepted(error, std::move(socket));
    });
  }

  void on_accepted(const boost::system::error_code& error, tcp::socket socket) {
    if (stopped || !acceptor.is_open()) return;
    if (error) {
      // Aborted: stop() ran. Anything else is transient (descriptors exhausted, a client
      // that reset before we accepted it): try again shortly instead of giving up.
      if (error == boost::asio::error::operation_aborted) return;
      retry_timer.expires_after(accept_retry_delay);
      retry_timer.async_wait([self = shared_from_this()](const boost::system::error_code& e) {
        if (!e && !self->stopped) self->accept_next();
      });
      return;
    }
    ++accepted;
    // Copy: the handler may call stop(), which clears on_accept.
    const AcceptHandler handler = on_accept;
    accept_next();
    if (handler) handler(make_tcp_stream(std::move(socket), stream_options));
  }

  tcp::acceptor acceptor;
  boost::asio::steady_timer retry_timer;
  AcceptHandler on_accept;
  TcpStreamOptions stream_options;
  bool stopped = true;
  std::uint16_t port = 0;
  std::string address;
  std::uint64_t accepted = 0;
};

TcpServer::TcpServer(boost::asio::io_context& io, AcceptHandler on_accept)
    : io_(io), on_accept_(std::move(on_accept)) {}

TcpServer::~TcpServer() { stop(); }

Status TcpServer::listen(const TcpServerOptions& options) {
  stop();
  auto state = std::make_shared<State>(io_);
  const std::string address = listen_address(options);
  const tcp::endpoint endpoint(
      options.allow_remote ? boost::asio::ip::address_v4::any() : boost::asio::ip::address_v4::loopback(),
      options.port);

  boost::system::error_code error;
  state->acceptor.open(endpoint.protocol(), error);
  if (error) return system_error(error, "cannot open a socket for " + address);
  // SO_REUSEADDR lets a restarted server take over a port whose old connections sit in
  // TIME_WAIT; on Linux it still refuses a port that another socket is listening on.
  state->acceptor.set_option(tcp::acceptor::reuse_address(true), error);
  if (error) return system_error(error, "cannot set SO_REUSEADDR on " + address);
  state->acceptor.bind(endpoint, error);
  if (error == boost::asio::error::address_in_use) return address_in_use(address);
  if (error == boost::asio::error::access_denied) {
    return bind_error(std::errc::permission_denied,
                      "not allowed to listen on " + address + " (ports below 1024 need privileges)");
  }
  if (error) return system_error(error, "cannot bind " + address);
  state->acceptor.listen(boost::asio::socket_base::max_listen_connections, error);
  if (error == boost::asio::error::address_in_use) return address_in_use(address);
  if (error) return system_error(error, "cannot listen on " + address);

  state->port = state->acceptor.local_endpoint(error).port();
  if (error) return system_error(error, "cannot read the bound port of " + address);
  state->address = endpoint.address().to_string() + ":" + std::to_string(state->port);
  state->on_accept = on_accept_;
  state->stream_options = options.stream;
  state->stopped = false;
  state->accept_next();
  state_ = std::move(state);
  return Ok{};
}

void TcpServer::stop() {
  if (!state_) return;
  state_->stopped = true;
  state_->on_accept = nullptr;
  boost::system::error_code ignored;
  state_->acceptor.close(ignored);
  state_->retry_timer.cancel();
  state_.reset();
}

bool TcpServer::listening() const { return state_ != nullptr; }
std::uint16_t TcpServer::port() const { return state_ ? state_->port : 0; }
std::string TcpServer::local_address() const { return state_ ? state_->address : std::string(); }
std::uint64_t TcpServer::accepted_count() const { return state_ ? state_->accepted : 0; }

}  // namespace ocp
