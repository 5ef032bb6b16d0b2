#pragma once
// Internals of the web view endpoint shared by the server and its connections (not installed).
// One io_context thread runs all of it: no locks, no strands.
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <array>
#include <chrono>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "player_app/webview/drop_log.hpp"
#include "player_app/webview/messages.hpp"
#include "player_app/webview_server.hpp"

namespace ocp {

namespace beast = boost::beast;
namespace http = boost::beast::http;
namespace websocket = boost::beast::websocket;
using tcp = boost::asio::ip::tcp;

class WebsocketSession;
class HttpSession;

// What the web view turns away, each logged once per episode (RefusalLog).
enum class Refusal {
  origin,             // 403: a foreign Origin
  host,               // 421: a foreign Host (DNS rebinding)
  busy,               // 503 at accept: no slot, none to reclaim
  reclaimed,          // a stalled request closed to make room
  timeout,            // a request not complete in time
  header_too_large,   // 431
  bad_request,        // 400/413: not HTTP we take
  websocket_full,     // 503: max_clients pages connected
  path,               // 403: a traversal or other refused path
};
inline constexpr std::size_t refusal_kind_count = 9;

// Refusals are logged per episode, never per request (a scanner or a hostile page would flood
// the log) and never only once per process (a second attack hours later must show): the
// first refusal of a kind is a warning with its details; the following ones are counted
// while they keep coming, and when `gap` passes without one the episode ends with one line
// giving the count. The next refusal of that kind starts a new episode.
class RefusalLog {
 public:
  RefusalLog(Executor& executor, Logger logger, Micros gap);
  ~RefusalLog();
  RefusalLog(const RefusalLog&) = delete;
  RefusalLog& operator=(const RefusalLog&) = delete;

  void note(Refusal kind, std::string detail);
  // Ends every open episode now (the server stops).
  void flush();

 private:
  struct Episode {
    std::uint64_t count = 0;
    SimTime started{0};
    SimTime last{0};
    std::string last_detail;
    std::optional<Executor::TimerId> timer;
  };
  void check_end(Refusal kind);
  void end(Refusal kind);

  Executor& executor_;
  Logger logger_;
  Micros gap_;
  std::array<Episode, refusal_kind_count> episodes_{};
  std::shared_ptr<int> alive_ = std::make_shared<int>(0);
};

// One connection's share of the limits: an HTTP slot (until it becomes a WebSocket) and one
// of its address's max_connections_per_address. Given back once, by release() or when it is
// destroyed. The Hub must outlive it (the sessions that own slots hold the Hub).
class ConnectionSlot {
 public:
  ConnectionSlot() = default;
  ConnectionSlot(WebviewServer::Hub& hub, std::string address);
  ConnectionSlot(ConnectionSlot&& other) noexcept;
  ConnectionSlot& operator=(ConnectionSlot&& other) noexcept;
  ConnectionSlot(const ConnectionSlot&) = delete;
  ConnectionSlot& operator=(const ConnectionSlot&) = delete;
  ~ConnectionSlot() { release(); }

  void leave_http();   // the connection became a WebSocket: the HTTP slot is free, the address's is not
  void release();

 private:
  WebviewServer::Hub* hub_ = nullptr;
  std::string address_;
  bool http_ = false;
};

struct WebviewServer::Hub : std::enable_shared_from_this<WebviewServer::Hub> {
  Hub(AsioExecutor& executor, WebviewOptions options, Logger logger);

  void accept_next();
  // A new connection: admitted with a slot, or told 503 and closed.
  void admit(tcp::socket socket);
  // Frees a slot for a newcomer from `address` if one is needed and can be had; false: refuse it.
  bool make_room(const std::string& address);
  std::size_t connections_of(const std::string& address) const;   // HTTP and WebSocket
  // Tells the peer `response` (a whole HTTP response, Connection: close) and closes, without
  // holding a slot; at most max_refused_connections at once, further ones are closed at once.
  void send_and_close(tcp::socket socket, std::string response);
  void on_frame(const VehicleOcpShared& shared);
  // A complete text message from a page (already size- and rate-checked).
  void on_message(WebsocketSession& session, std::string_view text);
  void broadcast(const std::shared_ptr<const std::string>& message);
  webview::Status current_status() const;
  std::shared_ptr<const std::string> status_message() const;

  AsioExecutor& executor;
  WebviewOptions options;
  Logger logger;
  WebviewLimits limits;
  tcp::acceptor acceptor;
  std::string address;                 // "127.0.0.1:4002"
  std::string bound_host;              // "127.0.0.1" or "0.0.0.0"
  std::uint16_t bound_port = 0;
  std::vector<std::string> allowed_origins;   // options.allowed_origins, normalised
  std::filesystem::path root;
  PlayerCore* player = nullptr;
  const sim_app::PairRejectionNotes* loop_notes = nullptr;
  bool stopped = false;
  std::map<std::uint64_t, std::weak_ptr<WebsocketSession>> sessions;
  std::uint64_t next_session_id = 1;
  std::map<std::uint64_t, std::weak_ptr<HttpSession>> http_sessions;
  std::uint64_t next_http_id = 1;
  std::size_t http_connections = 0;                        // ConnectionSlot keeps these
  std::map<std::string, std::size_t> connections_per_address;
  std::size_t refused_connections = 0;                     // being told why and closed
  RefusalLog refusals;
  std::optional<webview::Status> last_status;
  std::string json_buffer;
  WebviewStats stats;
};

// "HTTP/1.1 503 Service Unavailable" with a text body and Connection: close, as bytes (for
// refusals sent before a request was read, and after one that will not be answered otherwise).
std::string refusal_response(http::status status, std::string_view body, bool head_request = false);

// One plain HTTP connection: static files, or the upgrade to a WebsocketSession at /ws.
class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(std::shared_ptr<WebviewServer::Hub> hub, tcp::socket socket, ConnectionSlot slot, std::uint64_t id);
  ~HttpSession();
  void start() { read_request(); }

  // Since when this connection has waited for a request that is not complete yet (an idle
  // keep-alive connection too); nullopt while it answers one.
  const std::optional<SimTime>& waiting_since() const { return waiting_since_; }
  const std::string& remote_address() const { return remote_address_; }
  const std::string& peer() const { return peer_; }
  // Closes it to make room for another connection; its slot is free when this returns.
  void reclaim();

 private:
  void read_request();
  void read_more();
  void on_read(beast::error_code error, std::size_t bytes);
  void handle(http::request<http::string_body>&& request);
  // The Host and Origin rules (webview_server.hpp); true when the request was refused.
  bool refuse_foreign(const http::request<http::string_body>& request);
  void upgrade(http::request<http::string_body>&& request);
  void serve(const http::request<http::string_body>& request);
  void reply_text(const http::request<http::string_body>& request, http::status status, std::string body);
  // Logs (per episode), answers `status` with Connection: close and closes; the slot is free at once.
  void refuse(Refusal kind, std::string detail, http::status status, std::string_view body, bool head_request = false);
  void shut_down();
  template <class Body>
  void write(http::response<Body>&& response);

  std::shared_ptr<WebviewServer::Hub> hub_;
  beast::tcp_stream stream_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  std::shared_ptr<void> response_;   // kept alive while it is written
  std::string peer_;                 // "127.0.0.1:53312"
  std::string remote_address_;       // "127.0.0.1"
  std::string local_host_;           // the address this connection came to
  std::uint16_t local_port_ = 0;
  std::uint64_t id_;
  ConnectionSlot slot_;
  std::optional<SimTime> waiting_since_;
  std::chrono::steady_clock::time_point request_deadline_;
};

// One web view page over a WebSocket.
class WebsocketSession : public std::enable_shared_from_this<WebsocketSession> {
 public:
  WebsocketSession(std::shared_ptr<WebviewServer::Hub> hub, tcp::socket socket, std::string peer, std::uint64_t id,
                   ConnectionSlot slot);
  void start(http::request<http::string_body> request);
  // Queues a message; a page that lets max_queued_messages pile up is disconnected.
  void send(std::shared_ptr<const std::string> message);
  // Drops the connection at once (no close handshake), logging `reason`.
  void close(const std::string& reason);
  // Reports a dropped message: logged once per kind then summarised; the page is told once.
  void drop(webview::DropKind kind, std::string_view detail);
  const std::string& peer() const { return peer_; }

 private:
  void read();
  void on_read(beast::error_code error);
  void write_next();

  std::shared_ptr<WebviewServer::Hub> hub_;
  websocket::stream<beast::tcp_stream> ws_;
  beast::flat_buffer buffer_;
  std::string peer_;
  std::uint64_t id_;
  ConnectionSlot slot_;
  std::deque<std::shared_ptr<const std::string>> queue_;
  bool writing_ = false;
  bool open_ = false;
  bool closed_ = false;
  webview::DropLog drops_;
  webview::RateLimiter rate_;
};

}  // namespace ocp
