#pragma once
// One TCP front for both APIs: a TcpServer on 127.0.0.1 (0.0.0.0 with ocp_tcp_allow_remote)
// that hands every accepted socket to a core. Everything after the accept — one active
// connection, refusing a second, the 2 s read timeout, draining oversized frames, closing on
// malformed input — is the core's, so TCP and in-memory pipes behave the same.
//   * the Streamer's vehicle API (SPEC §3.1): vehicle_api_front(), sockets go to one World
//     vehicle's StreamerCore (World::accept_vehicle_connection);
//   * the Player's operator API (SPEC §4.2): operator_api_front(), sockets go to
//     PlayerCore::accept_client_connection (the `tcp` client-data source).
// Connections are handed over as they are accepted, i.e. while the io_context runs; the world
// must be started by then (listening before world.start() is fine).
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "ocp/asio/executor.hpp"
#include "ocp/byte_stream.hpp"
#include "ocp/log.hpp"
#include "ocp/asio/tcp_server.hpp"
#include "world/world.hpp"

namespace ocp::sim_app {

class TcpFront {
 public:
  using Accept = std::function<void(std::shared_ptr<ByteStream>)>;

  // `api` names the front in its log lines ("vehicle API", "operator API"); `detail` is added
  // to the listening line ("for vehicle 'truck-1'"), or empty.
  TcpFront(AsioExecutor& executor, std::string api, std::string detail, Accept accept, Logger logger);
  // Listens and logs "<api> listening on 127.0.0.1:4000 <detail>". Port in use → the error
  // of TcpServer::listen (std::errc::address_in_use).
  [[nodiscard]] Status listen(const TcpServerOptions& options);
  void stop();

  bool listening() const { return server_.listening(); }
  std::uint16_t port() const { return server_.port(); }
  std::string address() const { return server_.local_address(); }
  std::uint64_t accepted_count() const { return accepted_; }

 private:
  std::string api_;
  std::string detail_;
  Accept accept_;
  Logger logger_;
  TcpServer server_;
  std::uint64_t accepted_ = 0;
};

// The Streamer's vehicle API for `vehicle` of `world`.
std::unique_ptr<TcpFront> vehicle_api_front(AsioExecutor& executor, World& world, std::string vehicle, Logger logger);
// The Player's operator API of `world`.
std::unique_ptr<TcpFront> operator_api_front(AsioExecutor& executor, World& world, Logger logger);

}  // namespace ocp::sim_app
