// One HTTP connection of the web view: static files (GET/HEAD) and the WebSocket upgrade.
#include <chrono>
#include <utility>

#include "player_app/webview/static_files.hpp"
#include "webview_hub.hpp"

namespace ocp {
namespace {

constexpr std::chrono::seconds http_idle_timeout{30};
constexpr std::size_t max_header_bytes = 8 * 1024;
constexpr std::size_t max_request_body_bytes = 4 * 1024;   // GET/HEAD carry none
constexpr const char* websocket_path = "/ws";

std::string peer_of(const tcp::socket& socket) {
  boost::system::error_code error;
  const auto endpoint = socket.remote_endpoint(error);
  if (error) return "?";
  return endpoint.address().to_string() + ":" + std::to_string(endpoint.port());
}

}  // namespace

HttpSession::HttpSession(std::shared_ptr<WebviewServer::Hub> hub, tcp::socket socket)
    : hub_(std::move(hub)), stream_(std::move(socket)) {
  peer_ = peer_of(stream_.socket());
  ++hub_->http_connections;
}

HttpSession::~HttpSession() { --hub_->http_connections; }

void HttpSession::read_request() {
  if (hub_->stopped) return;
  parser_.emplace();
  parser_->header_limit(max_header_bytes);
  parser_->body_limit(max_request_body_bytes);
  stream_.expires_after(http_idle_timeout);
  http::async_read(stream_, buffer_, *parser_,
                   [self = shared_from_this()](beast::error_code error, std::size_t) { self->on_request(error); });
}

void HttpSession::on_request(beast::error_code error) {
  if (error == http::error::end_of_stream || error == beast::error::timeout ||
      error == boost::asio::error::operation_aborted || error == boost::asio::error::connection_reset) {
    beast::error_code ignored;
    stream_.socket().shutdown(tcp::socket::shutdown_both, ignored);
    return;
  }
  if (error) {
    hub_->note_refusal("HTTP request from " + peer_ + " not understood: " + error.message());
    beast::error_code ignored;
    stream_.socket().shutdown(tcp::socket::shutdown_both, ignored);
    return;
  }
  ++hub_->stats.http_requests;
  http::request<http::string_body> request = parser_->release();
  if (websocket::is_upgrade(request)) {
    upgrade(std::move(request));
    return;
  }
  serve(request);
}

void HttpSession::upgrade(http::request<http::string_body>&& request) {
  if (request.target() != websocket_path) {
    reply_text(request, http::status::not_found, "the web view WebSocket is at /ws\n");
    return;
  }
  if (hub_->sessions.size() >= hub_->limits.max_clients) {
    ++hub_->stats.websocket_refused;
    hub_->note_refusal("WebSocket client " + peer_ + " refused: " + std::to_string(hub_->limits.max_clients) +
                       " web view clients already connected");
    reply_text(request, http::status::service_unavailable, "too many web view clients\n");
    return;
  }
  const std::uint64_t id = hub_->next_session_id++;
  stream_.expires_never();   // the WebSocket has its own timeouts
  auto session = std::make_shared<WebsocketSession>(hub_, stream_.release_socket(), peer_, id);
  session->start(std::move(request));
}

void HttpSession::serve(const http::request<http::string_body>& request) {
  if (request.method() != http::verb::get && request.method() != http::verb::head) {
    reply_text(request, http::status::method_not_allowed, "only GET and HEAD\n");
    return;
  }
  const webview::ResolvedFile file = webview::resolve_static_file(hub_->root, std::string_view(request.target().data(), request.target().size()));
  switch (file.outcome) {
    case webview::FileLookup::bad_request:
      reply_text(request, http::status::bad_request, file.reason + "\n");
      return;
    case webview::FileLookup::refused:
      ++hub_->stats.paths_refused;
      hub_->note_refusal("refused " + std::string(request.target().substr(0, 200)) + " from " + peer_ + ": " + file.reason);
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

template <class Body>
void HttpSession::write(http::response<Body>&& response) {
  auto owned = std::make_shared<http::response<Body>>(std::move(response));
  response_ = owned;
  stream_.expires_after(http_idle_timeout);
  http::async_write(stream_, *owned, [self = shared_from_this(), owned](beast::error_code error, std::size_t) {
    self->response_.reset();
    if (error || !owned->keep_alive()) {
      beast::error_code ignored;
      self->stream_.socket().shutdown(tcp::socket::shutdown_both, ignored);
      return;
    }
    self->read_request();
  });
}

}  // namespace ocp
