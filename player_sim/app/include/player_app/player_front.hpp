#pragma once
// The Player's operator-side TCP front (SPEC §4.2): a TcpServer on
// 127.0.0.1:ocp_player_tcp_port (0.0.0.0 with ocp_tcp_allow_remote) whose accepted sockets
// go to the World's PlayerCore::accept_client_connection — the `tcp` client-data source. One client at a
// time, the 2 s read timeout, framing and source locking are the core's rules.
#include <cstdint>
#include <string>

#include "ocp/asio_executor.hpp"
#include "ocp/log.hpp"
#include "ocp/tcp_server.hpp"
#include "world/world.hpp"

namespace ocp {

class PlayerFront {
 public:
  // Connections are handed over as they are accepted, i.e. while the io_context runs; the
  // world must be started by then (listening before world.start() is fine).
  PlayerFront(AsioExecutor& executor, World& world, Logger logger);
  // Listens and logs "operator API listening on 127.0.0.1:4001". Port in use → the error of
  // TcpServer::listen (std::errc::address_in_use, "address 127.0.0.1:4001 already in use").
  [[nodiscard]] Status listen(const TcpServerOptions& options);
  void stop();

  bool listening() const { return server_.listening(); }
  std::uint16_t port() const { return server_.port(); }
  std::string address() const { return server_.local_address(); }
  std::uint64_t accepted_count() const { return accepted_; }

 private:
  World& world_;
  Logger logger_;
  TcpServer server_;
  std::uint64_t accepted_ = 0;
};

}  // namespace ocp
