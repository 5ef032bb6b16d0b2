// The web view endpoint: listener, Player hook-up, broadcast and message dispatch.
#include <utility>

#include "ocp/json_codec.hpp"
#include "webview_hub.hpp"

namespace ocp {
namespace {

Error listen_error(const boost::system::error_code& error, const std::string& address) {
  if (error == boost::asio::error::address_in_use) {
    return Error{std::make_error_code(std::errc::address_in_use), "address " + address + " already in use"};
  }
  return Error{std::error_code(error.value(), std::system_category()),
               "web view cannot listen on " + address + ": " + error.message()};
}

}  // namespace

WebviewServer::Hub::Hub(AsioExecutor& executor_in, WebviewOptions options_in, Logger logger_in)
    : executor(executor_in),
      options(std::move(options_in)),
      logger(std::move(logger_in)),
      limits(options.limits),
      acceptor(executor_in.io()) {}

void WebviewServer::Hub::accept_next() {
  acceptor.async_accept([hub = shared_from_this()](boost::system::error_code error, tcp::socket socket) {
    if (hub->stopped || error == boost::asio::error::operation_aborted) return;
    if (!error) {
      if (hub->http_connections >= hub->limits.max_http_connections) {
        hub->note_refusal("connection closed: " + std::to_string(hub->limits.max_http_connections) +
                          " HTTP connections already open");
        boost::system::error_code ignored;
        socket.close(ignored);
      } else {
        std::make_shared<HttpSession>(hub, std::move(socket))->start();
      }
    }
    hub->accept_next();
  });
}

void WebviewServer::Hub::note_refusal(const std::string& what) {
  if (!refusal_warned) {
    refusal_warned = true;
    logger.warn("web view: {} (further refusals are logged at debug level)", what);
    return;
  }
  logger.debug("web view: {}", what);
}

webview::Status WebviewServer::Hub::current_status() const {
  webview::Status status;
  status.webview_clients = sessions.size();
  if (!player) return status;
  if (const auto source = player->locked_source()) status.locked_source = std::string(client_source_name(*source));
  status.client_data_stopped = player->client_data_stopped();
  status.active_vehicle = player->active_vehicle();
  status.vehicles = player->vehicles();
  return status;
}

std::shared_ptr<const std::string> WebviewServer::Hub::status_message() const {
  return std::make_shared<const std::string>(
      webview::make_envelope(webview::status_name, webview::encode_status(current_status())));
}

void WebviewServer::Hub::on_frame(const VehicleOcpShared& shared) {
  if (stopped || sessions.empty()) return;   // nobody listens: do not even encode
  encode_vehicle_ocp_shared(shared, json_buffer);
  broadcast(std::make_shared<const std::string>(webview::make_envelope(webview::vehicle_data_name, json_buffer)));
  ++stats.frames_published;
  // The lock state changes rarely; pages hear about it the frame it changes.
  webview::Status status = current_status();
  if (!last_status || *last_status != status) {
    last_status = status;
    broadcast(status_message());
  }
}

void WebviewServer::Hub::broadcast(const std::shared_ptr<const std::string>& message) {
  // send() may close a session, which erases it from `sessions`: iterate over a copy.
  const auto targets = sessions;
  for (const auto& [id, weak] : targets) {
    if (auto session = weak.lock()) session->send(message);
  }
}

void WebviewServer::Hub::on_message(WebsocketSession& session, std::string_view text) {
  ++stats.messages_received;
  auto message = webview::parse_envelope(text);
  if (!message) {
    session.drop(webview::DropKind::malformed, message.error().message());
    return;
  }
  if (message->name != webview::client_data_name) {
    session.drop(webview::DropKind::unknown_name,
                 "'" + message->name.substr(0, 64) + "' (the Player takes " + std::string(webview::client_data_name) + ")");
    return;
  }
  auto data = decode_client_ocp_shared(message->data_json);
  if (!data) {
    session.drop(webview::DropKind::malformed, std::string(webview::client_data_name) + ": " + data.error().message());
    return;
  }
  if (webview::is_keep_alive(*data)) {
    ++stats.keep_alives;   // SPEC §4.2 Decision: never locks the source
    return;
  }
  if (!player) return;
  ++stats.client_data_forwarded;
  player->handle_client_data(ClientSource::webview, *data);
}

WebviewServer::WebviewServer(AsioExecutor& executor, WebviewOptions options, Logger logger)
    : hub_(std::make_shared<Hub>(executor, std::move(options), std::move(logger))) {}

WebviewServer::~WebviewServer() { stop(); }

Status WebviewServer::listen() {
  Hub& hub = *hub_;
  std::error_code fs_error;
  if (!std::filesystem::is_directory(hub.options.root, fs_error)) {
    return Error{std::make_error_code(std::errc::no_such_file_or_directory),
                 "web view root '" + hub.options.root.string() + "' is not a folder"};
  }
  hub.root = hub.options.root;
  const auto ip = hub.options.allow_remote ? boost::asio::ip::address_v4::any() : boost::asio::ip::address_v4::loopback();
  const std::string wanted = ip.to_string() + ":" + std::to_string(hub.options.port);
  const tcp::endpoint endpoint(ip, hub.options.port);
  boost::system::error_code error;
  hub.acceptor.open(endpoint.protocol(), error);
  if (!error) hub.acceptor.set_option(tcp::acceptor::reuse_address(true), error);
  if (!error) hub.acceptor.bind(endpoint, error);
  if (!error) hub.acceptor.listen(boost::asio::socket_base::max_listen_connections, error);
  if (error) {
    boost::system::error_code ignored;
    hub.acceptor.close(ignored);
    return listen_error(error, wanted);
  }
  hub.address = ip.to_string() + ":" + std::to_string(hub.acceptor.local_endpoint().port());
  hub.stopped = false;
  hub.logger.info("web view on http://{}/ (WebSocket /ws, files from {})", hub.address, hub.root.string());
  hub.accept_next();
  return Ok{};
}

void WebviewServer::attach(PlayerCore& player) {
  hub_->player = &player;
  // PlayerCore has no way to remove a listener: the weak pointer makes a late call harmless.
  player.add_shared_listener([weak = std::weak_ptr<Hub>(hub_)](const VehicleOcpShared& shared) {
    if (auto hub = weak.lock()) hub->on_frame(shared);
  });
}

void WebviewServer::stop() {
  Hub& hub = *hub_;
  if (hub.stopped) return;
  hub.stopped = true;
  hub.player = nullptr;
  if (hub.acceptor.is_open()) {
    boost::system::error_code ignored;
    hub.acceptor.close(ignored);
    hub.logger.info("web view on http://{}/ closed", hub.address);
  }
  const auto sessions = hub.sessions;
  for (const auto& [id, weak] : sessions) {
    if (auto session = weak.lock()) session->close("the Player is shutting down");
  }
}

std::uint16_t WebviewServer::port() const {
  boost::system::error_code error;
  if (!hub_->acceptor.is_open()) return 0;
  const auto endpoint = hub_->acceptor.local_endpoint(error);
  return error ? 0 : endpoint.port();
}

std::string WebviewServer::address() const { return hub_->acceptor.is_open() ? hub_->address : std::string(); }
std::size_t WebviewServer::websocket_clients() const { return hub_->sessions.size(); }
const WebviewStats& WebviewServer::stats() const { return hub_->stats; }

}  // namespace ocp
