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
#include <deque>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
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

  // Connects and completes the handshake (runs the io_context meanwhile). `read`: false makes
  // a page that never reads (for the slow-reader test).
  bool connect(boost::asio::io_context& io, std::uint16_t port, bool read = true, int receive_buffer_bytes = 0) {
    auto& socket = beast::get_lowest_layer(ws_).socket();
    socket.open(tcp::v4());
    if (receive_buffer_bytes > 0) socket.set_option(boost::asio::socket_base::receive_buffer_size(receive_buffer_bytes));
    boost::system::error_code error;
    socket.connect({boost::asio::ip::address_v4::loopback(), port}, error);
    if (error) return false;
    bool done = false;
    ws_.async_handshake("127.0.0.1", "/ws", [&](beast::error_code handshake_error) {
      done = true;
      handshake_error_ = handshake_error;
    });
    if (!run_until(io, [&] { return done; }) || handshake_error_) return false;
    if (read) read_next();
    return true;
  }

  void send(std::string text, bool binary = false) {
    queue_.push_back({std::move(text), binary});
    if (!writing_) write_next();
  }

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
    ws_.async_write(boost::asio::buffer(queue_.front().text), [this](beast::error_code error, std::size_t) {
      queue_.pop_front();
      if (error) {
        closed_ = true;
        queue_.clear();
        writing_ = false;
        return;
      }
      write_next();
    });
  }

  websocket::stream<beast::tcp_stream> ws_;
  beast::flat_buffer buffer_;
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

// GET `target` verbatim (no normalisation, unlike curl or a browser).
inline HttpReply http_get(boost::asio::io_context& io, std::uint16_t port, const std::string& target) {
  beast::tcp_stream stream(io);
  boost::system::error_code error;
  stream.socket().connect({boost::asio::ip::address_v4::loopback(), port}, error);
  if (error) return {};
  http::request<http::empty_body> request{http::verb::get, target, 11};
  request.set(http::field::host, "127.0.0.1");
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
