#pragma once
// The Streamer's vehicle-side TCP front (SPEC §3.1): a TcpServer on 127.0.0.1:tcp_port
// (0.0.0.0 with ocp_tcp_allow_remote) whose accepted sockets go to one World vehicle's
// StreamerCore. Everything else — one active connection, refusing a second, the 2 s read
// timeout, draining oversized frames, closing on malformed input, discarding stale control
// frames — is the core's, so TCP and in-memory pipes behave the same.
#include <cstdint>
#include <string>

#include "ocp/asio_executor.hpp"
#include "ocp/log.hpp"
#include "ocp/tcp_server.hpp"
#include "world/world.hpp"

namespace ocp {

class StreamerFront {
 public:
  StreamerFront(AsioExecutor& executor, World& world, std::string vehicle, Logger logger);
  // Listens and logs "vehicle API listening on 127.0.0.1:4000". Port in use → the error of
  // TcpServer::listen (std::errc::address_in_use, "address 127.0.0.1:4000 already in use").
  [[nodiscard]] Status listen(const TcpServerOptions& options);
  void stop();

  bool listening() const { return server_.listening(); }
  std::uint16_t port() const { return server_.port(); }
  std::string address() const { return server_.local_address(); }
  std::uint64_t accepted_count() const { return accepted_; }

 private:
  World& world_;
  std::string vehicle_;
  Logger logger_;
  TcpServer server_;
  std::uint64_t accepted_ = 0;
};

}  // namespace ocp
