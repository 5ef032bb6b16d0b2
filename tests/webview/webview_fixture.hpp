#pragma once
// Shared pieces of the web view tests: an async Boost.Beast WebSocket client and a one-shot
// HTTP GET, both on the test's io_context (the server runs on the same thread, so nothing may
// block), plus a temporary web root.
#include <unistd.h>

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <algorithm>
#include <deque>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "tcp_peers.hpp"
#include "player_app/webview/messages.hpp"

namespace ocp::testing {

namespace beast = boost::beast;
namespace http = boost::beast::http;
namespace websocket = boost::beast::websocket;
using tcp = boost::asio::ip::tcp;

// A page as the server sees it: every message received is kept (name, data JSON).
class WsClient {
 public:
  explicit WsClient(boost::asio::io_context& io) : ws_(io) {}

  // The handshake's Host (default "127.0.0.1:PORT", as a browser sends it) and Origin (sent
  // when not empty; a browser always sends one, non-browser clients often none).
  std::string host;
  std::string origin;
  std::string address = "127.0.0.1";   // where to connect (any 127/8 address is this machine)

  // Connects and completes the handshake (runs the io_context meanwhile). `read`: false makes
  // a page that never reads (for the slow-reader test).
  bool connect(boost::asio::io_context& io, std::uint16_t port, bool read = true, int receive_buffer_bytes = 0) {
    auto& socket = beast::get_lowest_layer(ws_).socket();
    socket.open(tcp::v4());
    if (receive_buffer_bytes > 0) socket.set_option(boost::asio::socket_base::receive_buffer_size(receive_buffer_bytes));
    boost::system::error_code error;
    socket.connect({boost::asio::ip::make_address_v4(address), port}, error);
    if (error) return false;
    if (!origin.empty()) {
      ws_.set_option(websocket::stream_base::decorator(
          [origin = origin](websocket::request_type& request) { request.set(http::field::origin, origin); }));
    }
    bool done = false;
    ws_.async_handshake(response_, host.empty() ? address + ":" + std::to_string(port) : host, "/ws",
                        [&](beast::error_code handshake_error) {
                          done = true;
                          handshake_error_ = handshake_error;
                        });
    if (!run_until(io, [&] { return done; }) || handshake_error_) return false;
    if (read) read_next();
    return true;
  }
  // The handshake's answer: 101 when it succeeded.
  unsigned handshake_status() const { return response_.result_int(); }

  // `fragment_bytes` > 0: the message goes out in frames of that size; 0: as one frame.
  void send(std::string text, bool binary = false, std::size_t fragment_bytes = 0) {
    queue_.push_back({std::move(text), binary, fragment_bytes});
    if (!writing_) write_next();
  }
  // Everything queued has been written.
  bool sent_all() const { return queue_.empty() && !writing_; }
  // Why the server closed (after closed()): the close frame's code, 0 without one.
  unsigned close_code() const { return closed_ ? static_cast<unsigned>(ws_.reason().code) : 0; }

  // Messages of that name received so far, as their "data" JSON.
  std::vector<std::string> data_of(std::string_view name) const {
    std::vector<std::string> found;
    for (const auto& message : messages_) {
      if (message.name == name) found.push_back(message.data_json);
    }
    return found;
  }
  std::size_t count(std::string_view name) const { return data_of(name).size(); }
  bool closed() const { return closed_; }
  const std::vector<webview::InboundMessage>& messages() const { return messages_; }

 private:
  struct Outgoing {
    std::string text;
    bool binary;
    std::size_t fragment_bytes;
  };

  void read_next() {
    ws_.async_read(buffer_, [this](beast::error_code error, std::size_t) {
      if (error) {
        closed_ = true;
        return;
      }
      auto message = webview::parse_envelope(beast::buffers_to_string(buffer_.data()));
      buffer_.consume(buffer_.size());
      if (message) messages_.push_back(std::move(*message));
      read_next();
    });
  }

  void write_next() {
    if (queue_.empty()) {
      writing_ = false;
      return;
    }
    writing_ = true;
    ws_.binary(queue_.front().binary);
    if (queue_.front().fragment_bytes == 0) {
      ws_.auto_fragment(false);
      ws_.async_write(boost::asio::buffer(queue_.front().text),
                      [this](beast::error_code error, std::size_t) { written(error); });
      return;
    }
    write_fragment(0);
  }

  void write_fragment(std::size_t offset) {
    const Outgoing& message = queue_.front();
    const std::size_t size = std::min(message.fragment_bytes, message.text.size() - offset);
    const bool last = offset + size == message.text.size();
    ws_.async_write_some(last, boost::asio::buffer(message.text.data() + offset, size),
                         [this, offset, size, last](beast::error_code error, std::size_t) {
                           if (error || last) return written(error);
                           write_fragment(offset + size);
                         });
  }

  void written(beast::error_code error) {
    queue_.pop_front();
    if (error) {
      closed_ = true;
      queue_.clear();
      writing_ = false;
      return;
    }
    write_next();
  }

  websocket::stream<beast::tcp_stream> ws_;
  beast::flat_buffer buffer_;
  websocket::response_type response_;
  beast::error_code handshake_error_;
  std::deque<Outgoing> queue_;
  bool writing_ = false;
  bool closed_ = false;
  std::vector<webview::InboundMessage> messages_;
};

struct HttpReply {
  unsigned status = 0;
  std::string content_type;
  std::string body;
};

// GET `target` verbatim (no normalisation, unlike curl or a browser), with Host
// 127.0.0.1:PORT and the extra `headers` (name, value).
inline HttpReply http_get(boost::asio::io_context& io, std::uint16_t port, const std::string& target,
                          const std::vector<std::pair<std::string, std::string>>& headers = {}) {
  beast::tcp_stream stream(io);
  boost::system::error_code error;
  stream.socket().connect({boost::asio::ip::address_v4::loopback(), port}, error);
  if (error) return {};
  http::request<http::empty_body> request{http::verb::get, target, 11};
  request.set(http::field::host, "127.0.0.1:" + std::to_string(port));
  for (const auto& [name, value] : headers) request.set(name, value);
  beast::flat_buffer buffer;
  http::response<http::string_body> response;
  bool done = false;
  http::async_write(stream, request, [&](beast::error_code write_error, std::size_t) {
    if (write_error) {
      done = true;
      return;
    }
    http::async_read(stream, buffer, response, [&](beast::error_code, std::size_t) { done = true; });
  });
  run_until(io, [&] { return done; });
  return {response.result_int(), std::string(response[http::field::content_type]), response.body()};
}

// A web root with a page, a script and a secret file next to (outside) it.
struct TempWebRoot {
  std::filesystem::path base;
  std::filesystem::path root;
  TempWebRoot() {
    base = std::filesystem::temp_directory_path() /
           ("ocp_webview_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter()++));
    root = base / "root";
    std::filesystem::create_directories(root / "app");
    write(root / "index.html", "<!doctype html><title>home</title>");
    write(root / "app" / "main.js", "console.log('hi');");
    write(root / "style.css", "body{}");
    write(base / "secret.txt", "do not serve");
    std::filesystem::create_symlink(base / "secret.txt", root / "link.txt");
  }
  ~TempWebRoot() {
    std::error_code ignored;
    std::filesystem::remove_all(base, ignored);
  }
  static void write(const std::filesystem::path& path, const std::string& text) { std::ofstream(path) << text; }
  static int& counter() {
    static int value = 0;
    return value;
  }
};

}  // namespace ocp::testing
