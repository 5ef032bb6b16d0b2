#pragma once
// Internals of the web view endpoint shared by the server and its connections (not installed).
// One io_context thread runs all of it: no locks, no strands.
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "player_app/webview/drop_log.hpp"
#include "player_app/webview/messages.hpp"
#include "player_app/webview_server.hpp"

namespace ocp {

namespace beast = boost::beast;
namespace http = boost::beast::http;
namespace websocket = boost::beast::websocket;
using tcp = boost::asio::ip::tcp;

class WebsocketSession;

struct WebviewServer::Hub : std::enable_shared_from_this<WebviewServer::Hub> {
  Hub(AsioExecutor& executor, WebviewOptions options, Logger logger);

  void accept_next();
  void on_frame(const VehicleOcpShared& shared);
  // A complete text message from a page (already size- and rate-checked).
  void on_message(WebsocketSession& session, std::string_view text);
  void broadcast(const std::shared_ptr<const std::string>& message);
  webview::Status current_status() const;
  std::shared_ptr<const std::string> status_message() const;
  // An HTTP path refused or a connection turned away: first one a warning, then debug lines,
  // so a scanner cannot flood the log (counts are in stats).
  void note_refusal(const std::string& what);

  AsioExecutor& executor;
  WebviewOptions options;
  Logger logger;
  WebviewLimits limits;
  tcp::acceptor acceptor;
  std::string address;
  std::filesystem::path root;
  PlayerCore* player = nullptr;
  bool stopped = false;
  std::map<std::uint64_t, std::weak_ptr<WebsocketSession>> sessions;
  std::uint64_t next_session_id = 1;
  std::size_t http_connections = 0;
  bool refusal_warned = false;
  std::optional<webview::Status> last_status;
  std::string json_buffer;
  WebviewStats stats;
};

// One plain HTTP connection: static files, or the upgrade to a WebsocketSession at /ws.
class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(std::shared_ptr<WebviewServer::Hub> hub, tcp::socket socket);
  ~HttpSession();
  void start() { read_request(); }

 private:
  void read_request();
  void on_request(beast::error_code error);
  void upgrade(http::request<http::string_body>&& request);
  void serve(const http::request<http::string_body>& request);
  void reply_text(const http::request<http::string_body>& request, http::status status, std::string body);
  template <class Body>
  void write(http::response<Body>&& response);

  std::shared_ptr<WebviewServer::Hub> hub_;
  beast::tcp_stream stream_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  std::shared_ptr<void> response_;   // kept alive while it is written
  std::string peer_;
};

// One web view page over a WebSocket.
class WebsocketSession : public std::enable_shared_from_this<WebsocketSession> {
 public:
  WebsocketSession(std::shared_ptr<WebviewServer::Hub> hub, tcp::socket socket, std::string peer, std::uint64_t id);
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
  std::size_t message_bytes_ = 0;
  bool discarding_ = false;   // the current message went over max_message_bytes
  std::deque<std::shared_ptr<const std::string>> queue_;
  bool writing_ = false;
  bool open_ = false;
  bool closed_ = false;
  webview::DropLog drops_;
  webview::RateLimiter rate_;
};

}  // namespace ocp
