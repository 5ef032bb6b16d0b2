#pragma once
// Helpers for real-socket tests on 127.0.0.1: drive an io_context until a condition holds
// (bounded by a generous timeout, never a fixed sleep), and a minimal framed client that
// collects every payload it receives.
#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "ocp/byte_stream.hpp"
#include "ocp/frame.hpp"
#include "ocp/tcp_stream.hpp"

namespace ocp::testing {

// Generous: the machine running the suite may be a loaded 2-core box.
inline constexpr std::chrono::milliseconds default_wait{10'000};

// Runs `io` until `done()` is true or `timeout` passed. Returns done().
inline bool run_until(boost::asio::io_context& io, const std::function<bool()>& done,
                      std::chrono::milliseconds timeout = default_wait) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!done()) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    if (io.stopped()) io.restart();
    if (io.run_one_for(std::chrono::milliseconds(5)) == 0 && io.stopped()) {
      // No work at all: nothing can change until something outside the loop does.
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }
  return true;
}

// Runs `io` for `duration` of wall time (to check that something does NOT happen).
inline void run_for(boost::asio::io_context& io, std::chrono::milliseconds duration) {
  const auto deadline = std::chrono::steady_clock::now() + duration;
  run_until(io, [&] { return std::chrono::steady_clock::now() >= deadline; }, duration * 2);
}

// A framed client over a real TCP connection; payloads are collected in order.
class LoopbackClient {
 public:
  explicit LoopbackClient(boost::asio::io_context& io) : io_(io) {}
  ~LoopbackClient() { close(); }

  // Blocking connect (the kernel completes it even before the server accepts).
  bool connect(std::uint16_t port) {
    boost::asio::ip::tcp::socket socket(io_);
    boost::system::error_code error;
    socket.connect({boost::asio::ip::address_v4::loopback(), port}, error);
    if (error) {
      connect_error_ = error.message();
      return false;
    }
    stream_ = make_tcp_stream(std::move(socket));
    auto alive = alive_;
    stream_->set_handlers(ByteStreamHandlers{
        [this, alive](std::string_view bytes) {
          if (*alive) on_bytes(bytes);
        },
        [this, alive](const std::string& reason) {
          if (!*alive) return;
          closed_ = true;
          close_reason_ = reason;
        }});
    return true;
  }

  void send_payload(std::string_view payload) {
    std::string frame;
    if (append_frame(payload, frame)) stream_->write(frame);
  }
  // Any bytes, e.g. a frame larger than the limit or a broken header.
  void send_raw(std::string_view bytes) { stream_->write(bytes); }
  void close() {
    *alive_ = false;
    alive_ = std::make_shared<bool>(true);
    if (stream_) stream_->close();
    stream_.reset();
  }

  // Called for each payload after it was stored (e.g. to echo at once).
  std::function<void(const std::string& payload)> on_payload;

  const std::vector<std::string>& payloads() const { return payloads_; }
  std::size_t payload_count() const { return payloads_.size(); }
  void clear_payloads() { payloads_.clear(); }
  bool closed_by_peer() const { return closed_; }
  const std::string& close_reason() const { return close_reason_; }
  const std::string& connect_error() const { return connect_error_; }
  bool connected() const { return stream_ && stream_->is_open() && !closed_; }

 private:
  void on_bytes(std::string_view bytes) {
    while (!bytes.empty()) {
      FrameEvent event;
      const std::size_t used = decoder_.put(bytes, event);
      bytes.remove_prefix(used);
      if (event.kind == FrameEvent::Kind::frame) {
        payloads_.emplace_back(event.payload);
        if (on_payload) on_payload(payloads_.back());
      }
      if (used == 0 && event.kind == FrameEvent::Kind::need_more) break;
    }
  }

  boost::asio::io_context& io_;
  std::shared_ptr<ByteStream> stream_;
  std::shared_ptr<bool> alive_ = std::make_shared<bool>(true);
  FrameDecoder decoder_;
  std::vector<std::string> payloads_;
  bool closed_ = false;
  std::string close_reason_;
  std::string connect_error_;
};

}  // namespace ocp::testing
