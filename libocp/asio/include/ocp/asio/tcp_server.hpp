#pragma once
// A listening TCP socket for the two OCP TCP APIs (SPEC §3.1, §4.2). It only accepts: every
// accepted socket becomes a ByteStream (TCP_NODELAY set) handed to `on_accept`; the protocol
// rules (one active connection, timeouts, framing) live in the cores that receive it.
//
//   TcpServer server(io, [&](std::shared_ptr<ByteStream> s) { core.accept_vehicle_connection(s); });
//   if (auto status = server.listen({.port = 4000}); !status) { /* status.error().detail */ }
//   … server.port() is the bound port (useful with port 0 = ephemeral) …
//   server.stop();
#include <boost/asio/io_context.hpp>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "ocp/byte_stream.hpp"
#include "ocp/error.hpp"
#include "ocp/asio/tcp_stream.hpp"

namespace ocp {

struct TcpServerOptions {
  std::uint16_t port = 0;       // 0 = an ephemeral port chosen by the system (see port())
  bool allow_remote = false;    // false: 127.0.0.1; true: 0.0.0.0 (ocp_tcp_allow_remote)
  // Every accepted stream's: the close grace, and a 64 KiB send buffer (about 1.5 s of
  // control frames; 4 of the largest frames).
  TcpStreamOptions stream{std::chrono::milliseconds{1000}, 64 * 1024};
};

// "127.0.0.1:4000" or "0.0.0.0:4000".
std::string listen_address(const TcpServerOptions& options);

class TcpServer {
 public:
  using AcceptHandler = std::function<void(std::shared_ptr<ByteStream>)>;

  // `on_accept` runs on the io_context's thread for every accepted connection.
  TcpServer(boost::asio::io_context& io, AcceptHandler on_accept);
  ~TcpServer();  // stops listening
  TcpServer(const TcpServer&) = delete;
  TcpServer& operator=(const TcpServer&) = delete;

  // Binds (SO_REUSEADDR on, so a port in TIME_WAIT is reusable) and starts accepting.
  // A port another socket listens on fails with std::errc::address_in_use and the detail
  // "another socket listens on 127.0.0.1:4000" (message(): "Address already in use: another
  // socket listens on 127.0.0.1:4000"); other failures name the address and the cause.
  [[nodiscard]] Status listen(const TcpServerOptions& options);
  // Stops accepting and closes the listening socket. Accepted streams are not touched.
  // Idempotent; listen() may be called again afterwards.
  void stop();

  bool listening() const;
  std::uint16_t port() const;          // the bound port; 0 when not listening
  std::string local_address() const;   // "127.0.0.1:54321"; "" when not listening
  std::uint64_t accepted_count() const;   // connections accepted since the last listen()

 private:
  struct State;
  boost::asio::io_context& io_;
  AcceptHandler on_accept_;
  // Shared with pending accept handlers, which may run after this object is gone.
  std::shared_ptr<State> state_;
};

}  // namespace ocp
