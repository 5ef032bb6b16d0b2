// One HTTP connection of the web view: the Host and Origin rules, bounded request reading,
// static files (GET/HEAD), the WebSocket upgrade, and refusals that close.
#include <algorithm>
#include <cctype>
#include <chrono>
#include <utility>

#include <fmt/format.h>

#include "player_app/webview/static_files.hpp"
#include "webview_hub.hpp"

namespace ocp {
namespace {

constexpr std::size_t max_header_bytes = 8 * 1024;
constexpr std::size_t max_request_body_bytes = 4 * 1024;   // GET/HEAD carry none
constexpr const char* websocket_path = "/ws";
constexpr std::size_t read_chunk_bytes = 4096;
// How long a refused connection may take to read its answer before it is closed.
constexpr std::chrono::seconds refusal_linger_time{1};
constexpr std::size_t refusal_linger_bytes = 64 * 1024;

std::string_view as_view(beast::string_view text) { return std::string_view(text.data(), text.size()); }

std::string endpoint_text(const tcp::endpoint& endpoint) {
  return endpoint.address().to_string() + ":" + std::to_string(endpoint.port());
}

std::string host_text(const boost::asio::ip::address& address) {
  return address.is_v6() ? "[" + address.to_string() + "]" : address.to_string();
}

// "LocalHost:4002" → "localhost:4002"; a Host without a port names port 80 (RFC 9110 §7.2).
std::string normalised_host(std::string_view host) {
  std::string lower(host);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  const std::size_t bracket = lower.rfind(']');
  const std::size_t colon = lower.rfind(':');
  const bool has_port = colon != std::string::npos && (bracket == std::string::npos || colon > bracket);
  return has_port ? lower : lower + ":80";
}

std::string seconds_text(std::chrono::milliseconds duration) {
  return fmt::format("{:g} s", std::chrono::duration<double>(duration).count());
}

// Tells a refused peer why and closes: writes the response, shuts the sending side down and
// reads (discarding) until the peer closes or refusal_linger_time passes. Closing at once
// with the peer's request still unread would reset the connection, and a reset may destroy
// the answer before the peer reads it (the "lingering close" of Apache and nginx).
class RefusedConnection : public std::enable_shared_from_this<RefusedConnection> {
 public:
  RefusedConnection(std::shared_ptr<WebviewServer::Hub> hub, tcp::socket socket, std::string response)
      : hub_(std::move(hub)), stream_(std::move(socket)), response_(std::move(response)) {
    ++hub_->refused_connections;
  }
  ~RefusedConnection() { --hub_->refused_connections; }

  void start() {
    stream_.expires_after(refusal_linger_time);
    boost::asio::async_write(stream_, boost::asio::buffer(response_),
                             [self = shared_from_this()](beast::error_code error, std::size_t) {
                               if (error) return self->close();
                               beast::error_code ignored;
                               self->stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
                               self->drain();
                             });
  }

 private:
  void drain() {
    stream_.async_read_some(boost::asio::buffer(scratch_), [self = shared_from_this()](beast::error_code error,
                                                                                       std::size_t bytes) {
      self->drained_ += bytes;
      if (error || self->drained_ > refusal_linger_bytes) return self->close();
      self->drain();
    });
  }
  void close() {
    beast::error_code ignored;
    stream_.socket().close(ignored);
  }

  std::shared_ptr<WebviewServer::Hub> hub_;
  beast::tcp_stream stream_;
  std::string response_;
  std::array<char, 4096> scratch_{};
  std::size_t drained_ = 0;
};

}  // namespace

std::string refusal_response(http::status status, std::string_view body, bool head_request) {
  std::string text = fmt::format(
      "HTTP/1.1 {} {}\r\nContent-Type: text/plain; charset=utf-8\r\nX-Content-Type-Options: nosniff\r\n"
      "Connection: close\r\nContent-Length: {}\r\n\r\n",
      static_cast<unsigned>(status), as_view(http::obsolete_reason(status)), body.size());
  if (!head_request) text += body;
  return text;
}

void WebviewServer::Hub::send_and_close(tcp::socket socket, std::string response) {
  if (refused_connections >= limits.max_refused_connections) {
    boost::system::error_code ignored;
    socket.close(ignored);
    return;
  }
  std::make_shared<RefusedConnection>(shared_from_this(), std::move(socket), std::move(response))->start();
}

HttpSession::HttpSession(std::shared_ptr<WebviewServer::Hub> hub, tcp::socket socket, ConnectionSlot slot,
                         std::uint64_t id)
    : hub_(std::move(hub)), stream_(std::move(socket)), id_(id), slot_(std::move(slot)) {
  boost::system::error_code error;
  const auto remote = stream_.socket().remote_endpoint(error);
  peer_ = error ? "?" : endpoint_text(remote);
  remote_address_ = error ? "?" : remote.address().to_string();
  const auto local = stream_.socket().local_endpoint(error);
  if (!error) {
    local_host_ = host_text(local.address());
    local_port_ = local.port();
  }
}

HttpSession::~HttpSession() { hub_->http_sessions.erase(id_); }

void HttpSession::reclaim() {
  waiting_since_.reset();
  hub_->http_sessions.erase(id_);
  slot_.release();
  beast::error_code ignored;
  stream_.socket().shutdown(tcp::socket::shutdown_both, ignored);
  stream_.close();
}

void HttpSession::shut_down() {
  waiting_since_.reset();
  hub_->http_sessions.erase(id_);
  slot_.release();
  beast::error_code ignored;
  stream_.socket().shutdown(tcp::socket::shutdown_both, ignored);
}

void HttpSession::read_request() {
  if (hub_->stopped) return shut_down();
  parser_.emplace();
  parser_->header_limit(max_header_bytes);
  parser_->body_limit(max_request_body_bytes);
  waiting_since_ = hub_->executor.now();
  request_deadline_ = std::chrono::steady_clock::now() + hub_->limits.header_timeout;
  if (buffer_.size() > 0) return on_read({}, 0);   // a pipelined request is already here
  read_more();
}

// Reads the socket here and feeds the parser, rather than http::async_read_some, because
// that one returns only once the whole header is in: every socket read gets its own expiry,
// the earlier of header_idle_timeout from now and the request's deadline, so a peer that
// trickles a byte now and then is closed at the deadline, one that goes silent after
// header_idle_timeout.
void HttpSession::read_more() {
  stream_.expires_at(std::min(std::chrono::steady_clock::now() + hub_->limits.header_idle_timeout, request_deadline_));
  stream_.async_read_some(buffer_.prepare(read_chunk_bytes),
                          [self = shared_from_this()](beast::error_code error, std::size_t bytes) {
                            self->on_read(error, bytes);
                          });
}

void HttpSession::on_read(beast::error_code error, std::size_t bytes) {
  if (!waiting_since_) return;   // reclaimed
  buffer_.commit(bytes);
  if (!error) {
    // One put takes the whole header or asks for more (need_more); after it, the body.
    while (buffer_.size() > 0 && !parser_->is_done()) {
      const std::size_t used = parser_->put(buffer_.data(), error);
      buffer_.consume(used);
      if (error == http::error::need_more) {
        error = {};
        break;
      }
      if (error || used == 0) break;
    }
    if (!error && !parser_->is_done()) return read_more();
  }
  if (error == beast::error::timeout) {
    // An idle keep-alive connection timing out is ordinary; a request begun and not finished is not.
    if (parser_->got_some() || buffer_.size() > 0) {
      ++hub_->stats.request_timeouts;
      const bool deadline = std::chrono::steady_clock::now() >= request_deadline_;
      hub_->refusals.note(Refusal::timeout,
                          fmt::format("closed the connection of {}: its request was not complete {}", peer_,
                                      deadline ? "within " + seconds_text(hub_->limits.header_timeout)
                                               : "and no byte came for " + seconds_text(hub_->limits.header_idle_timeout)));
    }
    return shut_down();
  }
  if (error == boost::asio::error::eof || error == boost::asio::error::operation_aborted ||
      error == boost::asio::error::connection_reset) {
    return shut_down();   // the peer went away (within a request or between two)
  }
  if (error == http::error::header_limit) {
    ++hub_->stats.headers_too_large;
    return refuse(Refusal::header_too_large,
                  fmt::format("request from {} refused with 431: headers over {} bytes", peer_, max_header_bytes),
                  http::status::request_header_fields_too_large, "request header fields too large (8 KiB at most)\n");
  }
  if (error == http::error::body_limit) {
    return refuse(Refusal::bad_request, fmt::format("request from {} refused with 413: a body over {} bytes", peer_,
                                                    max_request_body_bytes),
                  http::status::payload_too_large, "the web view takes GET and HEAD without a body\n");
  }
  if (error) {
    return refuse(Refusal::bad_request, "HTTP request from " + peer_ + " not understood: " + error.message(),
                  http::status::bad_request, "bad request\n");
  }
  waiting_since_.reset();
  ++hub_->stats.http_requests;
  handle(parser_->release());
}

void HttpSession::handle(http::request<http::string_body>&& request) {
  if (refuse_foreign(request)) return;
  if (websocket::is_upgrade(request)) {
    upgrade(std::move(request));
    return;
  }
  serve(request);
}

// Host: one of the names this web view answers to, with its port (DNS rebinding gives a page
// on evil.example the address 127.0.0.1, but its requests still say Host: evil.example).
// Origin, when present: this web view's own origin or an allowed one (RFC 6455 §10.2), so a
// page elsewhere cannot open the WebSocket. No Origin is served: browsers always send it on
// a WebSocket handshake (and on every cross-origin request that could read an answer), so
// only a non-browser client — which needs no page to reach a local port — leaves it out.
bool HttpSession::refuse_foreign(const http::request<http::string_body>& request) {
  const bool head = request.method() == http::verb::head;
  const std::string port = std::to_string(local_port_);
  const std::vector<std::string> own_hosts{"127.0.0.1", "localhost", hub_->bound_host, local_host_};
  const auto host_count = request.count(http::field::host);
  if (host_count > 1) {
    refuse(Refusal::bad_request, "request from " + peer_ + " refused: more than one Host", http::status::bad_request,
           "one Host header, please\n", head);
    return true;
  }
  if (host_count == 0) {
    if (request.version() >= 11) {   // HTTP/1.1 requires it (RFC 9112 §3.2); HTTP/1.0 had none
      refuse(Refusal::bad_request, "request from " + peer_ + " refused: no Host", http::status::bad_request,
             "no Host header\n", head);
      return true;
    }
  } else {
    const std::string host = normalised_host(as_view(request[http::field::host]));
    const bool own = std::any_of(own_hosts.begin(), own_hosts.end(),
                                 [&](const std::string& name) { return host == name + ":" + port; });
    if (!own) {
      ++hub_->stats.host_refused;
      refuse(Refusal::host,
             fmt::format("{} from {} refused with 421: Host '{}' is not this web view (127.0.0.1:{} or localhost:{})",
                         websocket::is_upgrade(request) ? "WebSocket" : "request", peer_,
                         as_view(request[http::field::host]).substr(0, 100), port, port),
             http::status::misdirected_request, "misdirected request: use http://127.0.0.1:" + port + "/\n", head);
      return true;
    }
  }
  const auto origin_count = request.count(http::field::origin);
  if (origin_count == 0) return false;
  const std::string_view origin_text = as_view(request[http::field::origin]);
  bool allowed = false;
  if (origin_count == 1) {
    if (const auto origin = parse_webview_origin(origin_text)) {
      const std::string suffix = local_port_ == 80 ? "" : ":" + port;
      allowed = std::any_of(own_hosts.begin(), own_hosts.end(),
                            [&](const std::string& name) { return *origin == "http://" + name + suffix; }) ||
                std::find(hub_->allowed_origins.begin(), hub_->allowed_origins.end(), *origin) !=
                    hub_->allowed_origins.end();
    }
  }
  if (allowed) return false;
  ++hub_->stats.origin_refused;
  refuse(Refusal::origin,
         fmt::format("{} from {} refused with 403: Origin '{}' is not this web view's "
                     "(allow another origin with --webview-allow-origin)",
                     websocket::is_upgrade(request) ? "WebSocket" : "request", peer_, origin_text.substr(0, 100)),
         http::status::forbidden, "forbidden: pages from another origin may not use the web view\n", head);
  return true;
}

void HttpSession::upgrade(http::request<http::string_body>&& request) {
  if (request.target() != websocket_path) {
    reply_text(request, http::status::not_found, "the web view WebSocket is at /ws\n");
    return;
  }
  if (hub_->sessions.size() >= hub_->limits.max_clients) {
    ++hub_->stats.websocket_refused;
    refuse(Refusal::websocket_full,
           "WebSocket client " + peer_ + " refused: " + std::to_string(hub_->limits.max_clients) +
               " web view clients already connected",
           http::status::service_unavailable, "too many web view clients\n");
    return;
  }
  const std::uint64_t id = hub_->next_session_id++;
  hub_->http_sessions.erase(id_);
  slot_.leave_http();
  stream_.expires_never();   // the WebSocket has its own timeouts
  auto session = std::make_shared<WebsocketSession>(hub_, stream_.release_socket(), peer_, id, std::move(slot_));
  session->start(std::move(request));
}

void HttpSession::serve(const http::request<http::string_body>& request) {
  if (request.method() != http::verb::get && request.method() != http::verb::head) {
    reply_text(request, http::status::method_not_allowed, "only GET and HEAD\n");
    return;
  }
  const webview::ResolvedFile file = webview::resolve_static_file(hub_->root, as_view(request.target()));
  switch (file.outcome) {
    case webview::FileLookup::bad_request:
      reply_text(request, http::status::bad_request, file.reason + "\n");
      return;
    case webview::FileLookup::refused:
      ++hub_->stats.paths_refused;
      hub_->refusals.note(Refusal::path, "refused " + std::string(as_view(request.target()).substr(0, 200)) + " from " + peer_ +
                                             ": " + file.reason);
      reply_text(request, http::status::forbidden, "forbidden\n");
      return;
    case webview::FileLookup::not_found:
      reply_text(request, http::status::not_found, "not found\n");
      return;
    case webview::FileLookup::found:
      break;
  }
  http::file_body::value_type body;
  beast::error_code error;
  body.open(file.path.c_str(), beast::file_mode::scan, error);
  if (error) {
    reply_text(request, http::status::not_found, "not found\n");
    return;
  }
  ++hub_->stats.files_served;
  const auto size = body.size();
  const std::string type(webview::content_type_for(file.path));
  if (request.method() == http::verb::head) {
    http::response<http::empty_body> response{http::status::ok, request.version()};
    response.set(http::field::content_type, type);
    response.set("X-Content-Type-Options", "nosniff");
    response.content_length(size);
    response.keep_alive(request.keep_alive());
    write(std::move(response));
    return;
  }
  http::response<http::file_body> response{std::piecewise_construct, std::make_tuple(std::move(body)),
                                           std::make_tuple(http::status::ok, request.version())};
  response.set(http::field::content_type, type);
  response.set("X-Content-Type-Options", "nosniff");
  // Pages under development change often; the browser revalidates rather than caching.
  response.set(http::field::cache_control, "no-cache");
  response.content_length(size);
  response.keep_alive(request.keep_alive());
  write(std::move(response));
}

void HttpSession::reply_text(const http::request<http::string_body>& request, http::status status, std::string body) {
  http::response<http::string_body> response{status, request.version()};
  response.set(http::field::content_type, "text/plain; charset=utf-8");
  response.set("X-Content-Type-Options", "nosniff");
  response.keep_alive(request.keep_alive());
  response.body() = std::move(body);
  response.prepare_payload();
  write(std::move(response));
}

void HttpSession::refuse(Refusal kind, std::string detail, http::status status, std::string_view body,
                         bool head_request) {
  hub_->refusals.note(kind, std::move(detail));
  waiting_since_.reset();
  hub_->http_sessions.erase(id_);
  slot_.release();   // a refusal never holds a slot: the connection is only told why and closed
  stream_.expires_never();
  hub_->send_and_close(stream_.release_socket(), refusal_response(status, body, head_request));
}

template <class Body>
void HttpSession::write(http::response<Body>&& response) {
  auto owned = std::make_shared<http::response<Body>>(std::move(response));
  response_ = owned;
  stream_.expires_after(hub_->limits.response_timeout);
  http::async_write(stream_, *owned, [self = shared_from_this(), owned](beast::error_code error, std::size_t) {
    self->response_.reset();
    if (error || !owned->keep_alive()) return self->shut_down();
    self->read_request();
  });
}

}  // namespace ocp
