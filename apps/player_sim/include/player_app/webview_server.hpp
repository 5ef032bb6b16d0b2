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
// Only its own pages may use it (RFC 6455 §10.2): a request whose Origin header is present
// and is not this web view's origin (http://127.0.0.1:PORT, http://localhost:PORT, the bound
// or reached address) nor one of WebviewOptions::allowed_origins gets 403, so another web
// page in the operator's browser can neither open the WebSocket nor drive the vehicle. A
// request without Origin (curl, a non-browser WebSocket client) is served — a page cannot
// leave Origin out of a WebSocket handshake, and a local program needs no browser to reach
// the port. A Host that is not 127.0.0.1, localhost, the bound address or the address the
// connection came to (with the port) gets 421, which stops DNS rebinding.
//
// Every input is bounded: at most max_clients WebSockets, max_http_connections HTTP
// connections and max_connections_per_address connections from one address; a request
// header must arrive within header_timeout with no gap over header_idle_timeout and be at
// most 8 KiB (431 beyond); inbound messages up to webview::max_message_bytes (bigger: closed
// with 1009), max_messages_per_second per page (the excess dropped); a page that does not
// read is disconnected once max_queued_messages wait for it. Drops are logged once per kind
// and then summarised; refusals once per episode with a count.
//
//   WebviewServer server(executor, {.port = 0, .root = "build/web"}, logger);
//   if (auto status = server.listen(); !status) { … }   // before world.start()
//   server.attach(world.player());                        // after world.start()
//   … server.stop();
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "ocp/asio/executor.hpp"
#include "ocp/error.hpp"
#include "ocp/log.hpp"
#include "player/player_core.hpp"

namespace ocp {
namespace sim_app {
class PairRejectionNotes;
}

struct WebviewLimits {
  std::size_t max_clients = 16;                 // WebSocket clients at once; more get HTTP 503
  // Plain HTTP connections at once. When they are all taken (or max_connections_per_address
  // of one address are), the connection that has waited longest for its request (a slowloris,
  // an idle keep-alive connection), if for at least stalled_after, is closed to make room;
  // when there is none (all are being answered or are WebSockets), the newcomer gets 503 and
  // is closed (it never holds a slot). See Hub::make_room for why stalled_after is 0.
  std::size_t max_http_connections = 256;
  std::size_t max_connections_per_address = 32;   // HTTP and WebSocket connections of one address
  std::chrono::milliseconds stalled_after{0};
  // A request (header and the small body GET/HEAD may carry) must arrive within
  // header_timeout, with no gap between reads longer than header_idle_timeout; an idle
  // keep-alive connection is closed after header_idle_timeout too.
  std::chrono::milliseconds header_idle_timeout{10'000};
  std::chrono::milliseconds header_timeout{20'000};
  std::chrono::milliseconds response_timeout{30'000};   // to write one response
  // Connections being told 4xx/503 and closed (each for at most ~1 s); more are closed at once.
  std::size_t max_refused_connections = 64;
  // A refusal of a kind after this long without one starts a new episode: the first refusal of
  // an episode is logged with its details, the rest are counted and logged once, at its end.
  std::chrono::milliseconds refusal_episode_gap{10'000};
  std::size_t max_queued_messages = 256;        // per WebSocket client (~2.5 s of frames)
  double max_messages_per_second = 500.0;       // per WebSocket client, bursts of the same size
  // SO_SNDBUF of each WebSocket: small enough that a page that stops reading fills it (and
  // then max_queued_messages) within seconds instead of parking megabytes in the kernel.
  int socket_send_buffer_bytes = 64 * 1024;
};

struct WebviewOptions {
  std::uint16_t port = 4002;          // 0 = a free port chosen by the system (see port())
  bool allow_remote = false;          // ocp_tcp_allow_remote: 0.0.0.0 instead of 127.0.0.1
  std::filesystem::path root;         // static files; must be a folder
  // Other origins whose pages may use the web view (--webview-allow-origin), each
  // "scheme://host[:port]" as parse_webview_origin accepts it.
  std::vector<std::string> allowed_origins;
  WebviewLimits limits;
};

// Checks an origin, "scheme://host[:port]" without user info, path, query or fragment, and
// returns it as browsers send it in an Origin header: scheme and host in lower case, the
// scheme's default port left out ("HTTP://LocalHost:80" → "http://localhost"). The error
// detail says what is wrong ("expected scheme://host[:port] without a path, got '…'").
[[nodiscard]] Result<std::string> parse_webview_origin(std::string_view text);

struct WebviewStats {
  std::uint64_t http_requests = 0;
  std::uint64_t files_served = 0;
  std::uint64_t paths_refused = 0;          // traversal attempts and other refused paths
  std::uint64_t websocket_accepted = 0;
  std::uint64_t websocket_refused = 0;      // over max_clients
  std::uint64_t origin_refused = 0;         // 403: a foreign Origin (HTTP or WebSocket)
  std::uint64_t host_refused = 0;           // 421: a Host that is not this web view's
  std::uint64_t connections_refused = 0;    // 503 at accept: no slot and none to reclaim
  std::uint64_t connections_reclaimed = 0;  // stalled requests closed to make room
  std::uint64_t request_timeouts = 0;       // a request incomplete at header_timeout / idle timeout
  std::uint64_t headers_too_large = 0;      // 431
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
  // Why each vehicle's latency loop does not close, while it does not (the Streamers' open
  // InvalidMac episodes): shown in the status pages receive. Must outlive this server or its
  // stop(); nullptr (the default) shows none.
  void show_loop_notes(const sim_app::PairRejectionNotes* notes);
  // Closes the listener and every connection. Idempotent.
  void stop();

  std::uint16_t port() const;
  std::string address() const;        // "127.0.0.1:4002"; "" when not listening
  std::size_t websocket_clients() const;
  std::size_t http_connections() const;   // HTTP connections holding a slot
  const WebviewStats& stats() const;

  struct Hub;   // shared with the connections, which may outlive this object briefly

 private:
  std::shared_ptr<Hub> hub_;
};

}  // namespace ocp
