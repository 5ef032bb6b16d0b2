// One web view page over a WebSocket: bounded reads (size, rate), a bounded write queue.
#include <chrono>
#include <utility>

#include "webview_hub.hpp"

namespace ocp {

WebsocketSession::WebsocketSession(std::shared_ptr<WebviewServer::Hub> hub, tcp::socket socket, std::string peer,
                                   std::uint64_t id, ConnectionSlot slot)
    : hub_(std::move(hub)),
      ws_(std::move(socket)),
      peer_(std::move(peer)),
      id_(id),
      slot_(std::move(slot)),
      drops_(hub_->logger, peer_),
      rate_(hub_->limits.max_messages_per_second, hub_->limits.max_messages_per_second) {}

void WebsocketSession::start(http::request<http::string_body> request) {
  hub_->sessions[id_] = weak_from_this();
  beast::error_code ignored;
  beast::get_lowest_layer(ws_).socket().set_option(
      boost::asio::socket_base::send_buffer_size(hub_->limits.socket_send_buffer_bytes), ignored);
  websocket::stream_base::timeout timeouts = websocket::stream_base::timeout::suggested(beast::role_type::server);
  // Pings find pages that vanished without a close (a killed browser) within ~30 s.
  timeouts.idle_timeout = std::chrono::seconds(30);
  timeouts.keep_alive_pings = true;
  // The opening handshake's request is already read and the close handshake is a frame each
  // way: a peer that takes longer (after a 1009, say) is not worth its slot.
  timeouts.handshake_timeout = std::chrono::seconds(5);
  ws_.set_option(timeouts);
  // Beast counts the message across its frames and, over the limit, fails the read with
  // message_too_big after closing with 1009 (RFC 6455 §7.4.1) itself.
  ws_.read_message_max(webview::max_message_bytes);
  ws_.async_accept(request, [self = shared_from_this()](beast::error_code error) {
    if (self->closed_) return;
    if (error) {
      self->close("WebSocket handshake failed: " + error.message());
      return;
    }
    self->open_ = true;
    ++self->hub_->stats.websocket_accepted;
    self->hub_->logger.info("web view client {} connected ({} of at most {})", self->peer_,
                            self->hub_->sessions.size(), self->hub_->limits.max_clients);
    self->send(self->hub_->status_message());   // the banner is right before the first frame
    self->read();
  });
}

void WebsocketSession::read() {
  ws_.async_read(buffer_, [self = shared_from_this()](beast::error_code error, std::size_t) { self->on_read(error); });
}

void WebsocketSession::on_read(beast::error_code error) {
  if (closed_) return;
  if (error == websocket::error::closed) {
    close("closed by the page");
    return;
  }
  if (error == websocket::error::message_too_big) {
    ++hub_->stats.messages_dropped;
    close("a message over " + std::to_string(webview::max_message_bytes) +
          " bytes; closed with 1009 (message too big)");
    return;
  }
  if (error) {
    close("connection lost: " + error.message());
    return;
  }
  const SimTime now = hub_->executor.now();
  if (!rate_.admit(now)) {
    drop(webview::DropKind::flood,
         "more than " + std::to_string(static_cast<long>(hub_->limits.max_messages_per_second)) + " messages a second");
  } else if (ws_.got_binary()) {
    drop(webview::DropKind::binary, "binary message; the web view protocol is JSON text");
  } else {
    const auto data = buffer_.cdata();
    hub_->on_message(*this, std::string_view(static_cast<const char*>(data.data()), data.size()));
  }
  buffer_.consume(buffer_.size());
  if (!closed_) read();
}

void WebsocketSession::drop(webview::DropKind kind, std::string_view detail) {
  ++hub_->stats.messages_dropped;
  if (!drops_.dropped(kind, hub_->executor.now(), detail)) return;
  send(std::make_shared<const std::string>(
      webview::make_envelope(webview::error_name, webview::encode_error(webview::drop_kind_name(kind), detail))));
}

void WebsocketSession::send(std::shared_ptr<const std::string> message) {
  if (closed_ || !open_) return;
  if (queue_.size() >= hub_->limits.max_queued_messages) {
    ++hub_->stats.slow_clients_disconnected;
    close("not reading: " + std::to_string(queue_.size()) + " messages waiting for it; disconnected");
    return;
  }
  queue_.push_back(std::move(message));
  if (!writing_) write_next();
}

void WebsocketSession::write_next() {
  if (closed_ || queue_.empty()) {
    writing_ = false;
    return;
  }
  writing_ = true;
  ws_.text(true);
  ws_.async_write(boost::asio::buffer(*queue_.front()), [self = shared_from_this()](beast::error_code error, std::size_t) {
    if (self->closed_) return;
    if (error) {
      self->close("write failed: " + error.message());
      return;
    }
    self->queue_.pop_front();
    self->write_next();
  });
}

void WebsocketSession::close(const std::string& reason) {
  if (closed_) return;
  closed_ = true;
  queue_.clear();
  hub_->sessions.erase(id_);
  slot_.release();
  drops_.flush();
  if (open_) {
    ++hub_->stats.websocket_closed;
    hub_->logger.info("web view client {} disconnected: {}", peer_, reason);
  } else {
    hub_->logger.warn("web view client {}: {}", peer_, reason);
  }
  // Abrupt on purpose: a page that does not read would never complete a close handshake.
  beast::error_code ignored;
  auto& socket = beast::get_lowest_layer(ws_).socket();
  socket.shutdown(tcp::socket::shutdown_both, ignored);
  socket.close(ignored);
}

}  // namespace ocp
