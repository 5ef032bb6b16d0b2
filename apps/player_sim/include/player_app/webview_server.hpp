#pragma once
// The web view endpoint of player_sim (docs/webview.md): one HTTP + WebSocket port
// (Boost.Beast) on 127.0.0.1 (0.0.0.0 with ocp_tcp_allow_remote) that
//   * serves static files from a root folder (the built-in dashboard by default), GET/HEAD
//     only, with path-traversal protection and proper content types;
//   * at /ws carries the web view's user messages as {"name", "data"} JSON text messages:
//     every Player frame the VehicleOcpShared object as ocp_vehicle_user_data, the
//     source-lock state as ocp_webview_status; from pages, ocp_client_user_data into
//     PlayerCore::handle_client_data(webview) — the `webview` source of SPEC §4.3, which the
//     Player stamps with the latest SEI pair itself, so u64 ack_time never passes through JS.
//
// Every input is bounded: at most max_clients WebSockets and max_http_connections HTTP
// connections; inbound messages up to webview::max_message_bytes (larger ones drained and
// dropped, over hard_message_limit_bytes the connection closes), max_messages_per_second
// per page (the excess dropped); a page that does not read is disconnected once
// max_queued_messages wait for it. Drops are logged once per kind and then summarised.
//
//   WebviewServer server(executor, {.port = 0, .root = "build/web"}, logger);
//   if (auto status = server.listen(); !status) { … }   // before world.start()
//   server.attach(world.player());                        // after world.start()
//   … server.stop();
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "ocp/asio_executor.hpp"
#include "ocp/error.hpp"
#include "ocp/log.hpp"
#include "player/player_core.hpp"

namespace ocp {

struct WebviewLimits {
  std::size_t max_clients = 16;                 // WebSocket clients at once; more get HTTP 503
  std::size_t max_http_connections = 64;        // plain HTTP connections at once; more are closed
  std::size_t max_queued_messages = 256;        // per WebSocket client (~2.5 s of frames)
  double max_messages_per_second = 500.0;       // per WebSocket client, bursts of the same size
  std::size_t hard_message_limit_bytes = 16u << 20;   // bigger: the connection is closed
  // SO_SNDBUF of each WebSocket: small enough that a page that stops reading fills it (and
  // then max_queued_messages) within seconds instead of parking megabytes in the kernel.
  int socket_send_buffer_bytes = 64 * 1024;
};

struct WebviewOptions {
  std::uint16_t port = 4002;          // 0 = a free port chosen by the system (see port())
  bool allow_remote = false;          // ocp_tcp_allow_remote: 0.0.0.0 instead of 127.0.0.1
  std::filesystem::path root;         // static files; must be a folder
  WebviewLimits limits;
};


struct WebviewStats {
  std::uint64_t http_requests = 0;
  std::uint64_t files_served = 0;
  std::uint64_t paths_refused = 0;          // traversal attempts and other refused paths
  std::uint64_t websocket_accepted = 0;
  std::uint64_t websocket_refused = 0;      // over max_clients
  std::uint64_t websocket_closed = 0;
  std::uint64_t slow_clients_disconnected = 0;
  std::uint64_t frames_published = 0;       // ocp_vehicle_user_data objects broadcast
  std::uint64_t messages_received = 0;      // complete text messages from pages
  std::uint64_t client_data_forwarded = 0;  // ocp_client_user_data handed to the Player
  std::uint64_t keep_alives = 0;            // ocp_client_user_data without client data
  std::uint64_t messages_dropped = 0;       // malformed, unknown name, oversized, binary, flood
};

class WebviewServer {
 public:
  WebviewServer(AsioExecutor& executor, WebviewOptions options, Logger logger);
  ~WebviewServer();   // stops
  WebviewServer(const WebviewServer&) = delete;
  WebviewServer& operator=(const WebviewServer&) = delete;

  // Binds and starts accepting; logs "web view on http://127.0.0.1:4002/". A busy port fails
  // with std::errc::address_in_use ("address 127.0.0.1:4002 already in use"); a root that is
  // not a folder fails too.
  [[nodiscard]] Status listen();
  // Connects the Player: frames are published from now on and client data goes to it.
  // The Player must outlive this server or its stop().
  void attach(PlayerCore& player);
  // Closes the listener and every connection. Idempotent.
  void stop();

  std::uint16_t port() const;
  std::string address() const;        // "127.0.0.1:4002"; "" when not listening
  std::size_t websocket_clients() const;
  const WebviewStats& stats() const;

  struct Hub;   // shared with the connections, which may outlive this object briefly

 private:
  std::shared_ptr<Hub> hub_;
};

}  // namespace ocp
