#pragma once
// Real sockets on 127.0.0.1 for the framed test peers: a client that connects to a port, a
// server that listens on an ephemeral port and gives every accepted connection its own peer,
// and the bounded real-time waits they are driven with (never a fixed sleep: drive the
// io_context until a condition holds, with a generous bound for a loaded 2-core machine).
//
//   TcpTestClient<VehiclePeer> vehicle(io, &executor);   // any FramedPeer role
//   ASSERT_TRUE(vehicle.connect(port));
//   ASSERT_TRUE(vehicle.wait_until([&] { return vehicle.received.size() >= 3; }));
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "framed_peer.hpp"
#include "ocp/asio/tcp_server.hpp"
#include "ocp/asio/tcp_stream.hpp"

namespace ocp::testing {

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

// A blocking connect to 127.0.0.1:port (the kernel completes it before the server accepts).
// nullptr, with the reason in `error`, when it fails.
inline std::shared_ptr<ByteStream> connect_loopback(boost::asio::io_context& io, std::uint16_t port,
                                                    std::string& error) {
  boost::asio::ip::tcp::socket socket(io);
  boost::system::error_code code;
  socket.connect({boost::asio::ip::address_v4::loopback(), port}, code);
  if (code) {
    error = code.message();
    return nullptr;
  }
  return make_tcp_stream(std::move(socket));
}

// A framed peer (any role) that connects over TCP.
template <class Peer = FramedPeer>
class TcpTestClient : public Peer {
 public:
  template <class... PeerArgs>
  explicit TcpTestClient(boost::asio::io_context& io, PeerArgs&&... peer_args)
      : Peer(std::forward<PeerArgs>(peer_args)...), io_(io) {}

  bool connect(std::uint16_t port) {
    auto stream = connect_loopback(io_, port, connect_error_);
    if (!stream) return false;
    this->attach(std::move(stream));
    return true;
  }
  const std::string& connect_error() const { return connect_error_; }

  bool wait_until(const std::function<bool()>& done, std::chrono::milliseconds timeout = default_wait) {
    return run_until(io_, done, timeout);
  }
  bool wait_for_frames(std::size_t count) {
    return wait_until([&] { return this->frames().size() >= count; });
  }
  bool wait_closed() {
    return wait_until([&] { return this->closed_by_peer(); });
  }

 private:
  boost::asio::io_context& io_;
  std::string connect_error_;
};

// Listens on 127.0.0.1, on an ephemeral port; every accepted connection gets its own Peer,
// made by `make_peer` (default: Peer constructed from nothing) and kept in accept order.
template <class Peer = FramedPeer>
class TcpTestServer {
 public:
  using MakePeer = std::function<std::unique_ptr<Peer>()>;

  explicit TcpTestServer(boost::asio::io_context& io, MakePeer make_peer = [] { return std::make_unique<Peer>(); })
      : io_(io), make_peer_(std::move(make_peer)), server_(io, [this](std::shared_ptr<ByteStream> stream) {
          peers_.push_back(make_peer_());
          peers_.back()->attach(std::move(stream));
          if (on_accept) on_accept(*peers_.back());
        }) {}

  [[nodiscard]] Status listen(std::uint16_t port = 0) { return server_.listen({.port = port}); }
  void stop() { server_.stop(); }
  std::uint16_t port() const { return server_.port(); }

  // Called with each new peer, once it is attached (e.g. to send a first message).
  std::function<void(Peer&)> on_accept;

  std::size_t accepted() const { return peers_.size(); }
  Peer& peer(std::size_t index) { return *peers_.at(index); }
  bool wait_for_accepts(std::size_t count, std::chrono::milliseconds timeout = default_wait) {
    return run_until(io_, [&] { return peers_.size() >= count; }, timeout);
  }

 private:
  boost::asio::io_context& io_;
  MakePeer make_peer_;
  std::vector<std::unique_ptr<Peer>> peers_;
  TcpServer server_;  // last: stops accepting before the peers go
};

}  // namespace ocp::testing
