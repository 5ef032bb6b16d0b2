// The web view against hostile peers, on real loopback sockets (issue #19): pages from another
// origin and DNS-rebound names, message sizes counted across frames, slowloris connections,
// oversized headers and one address holding its quota. Every wait is a bounded loop on a
// condition (tcp_peers.hpp run_until); the server's own timeouts are made small instead.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/write.hpp>
#include <chrono>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "captured_log.hpp"
#include "player_app/webview_server.hpp"
#include "webview_fixture.hpp"

namespace ocp {
namespace {

using namespace std::chrono_literals;
using testing::CapturedLog;
using testing::run_until;
using testing::WsClient;
using tcp = boost::asio::ip::tcp;

// A raw TCP client: writes what it is given (at once, or one byte every `interval` like a
// slowloris), keeps every byte the server sends and notes when the server closes.
class RawPeer {
 public:
  explicit RawPeer(boost::asio::io_context& io) : socket_(io), timer_(io) {}

  // From 127.0.0.1, or from `source` (another loopback address: another remote address to the server).
  bool connect(std::uint16_t port, const char* source = nullptr) {
    boost::system::error_code error;
    socket_.open(tcp::v4(), error);
    if (source) socket_.bind({boost::asio::ip::make_address_v4(source), 0}, error);
    if (!error) socket_.connect({boost::asio::ip::address_v4::loopback(), port}, error);
    if (error) return false;
    connected_ = true;
    read();
    return true;
  }
  void write(std::string bytes) {
    auto owned = std::make_shared<std::string>(std::move(bytes));
    boost::asio::async_write(socket_, boost::asio::buffer(*owned), [owned](boost::system::error_code, std::size_t) {});
  }
  void trickle(std::string bytes, std::chrono::milliseconds interval) {
    trickle_ = std::move(bytes);
    interval_ = interval;
    trickle_next();
  }
  void close() {
    boost::system::error_code ignored;
    timer_.cancel();
    socket_.close(ignored);
  }

  std::function<void()> on_closed;   // called once the server has closed the connection

  bool connected() const { return connected_; }
  bool closed_by_server() const { return closed_; }
  const std::string& received() const { return received_; }
  // The status of the server's answer ("HTTP/1.1 503 …" → 503); 0 before one.
  unsigned status() const {
    if (received_.size() < 12 || received_.compare(0, 5, "HTTP/") != 0) return 0;
    return static_cast<unsigned>(std::stoul(received_.substr(9, 3)));
  }

 private:
  void read() {
    socket_.async_read_some(boost::asio::buffer(chunk_), [this](boost::system::error_code error, std::size_t bytes) {
      received_.append(chunk_.data(), bytes);
      if (error) {
        closed_ = error != boost::asio::error::operation_aborted;
        timer_.cancel();
        if (closed_ && on_closed) on_closed();
        return;
      }
      read();
    });
  }
  void trickle_next() {
    if (sent_ >= trickle_.size() || closed_) return;
    write(trickle_.substr(sent_++, 1));
    timer_.expires_after(interval_);
    timer_.async_wait([this](boost::system::error_code error) {
      if (!error) trickle_next();
    });
  }

  tcp::socket socket_;
  boost::asio::steady_timer timer_;
  std::array<char, 4096> chunk_{};
  std::string received_;
  bool connected_ = false;
  bool closed_ = false;
  std::string trickle_;
  std::size_t sent_ = 0;
  std::chrono::milliseconds interval_{0};
};

// The start of a request that never ends: header lines one byte at a time, never the blank line.
std::string endless_request(std::uint16_t port) {
  std::string text = "GET / HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) + "\r\n";
  for (int line = 0; line < 100; ++line) text += "X-Slow-" + std::to_string(line) + ": still coming\r\n";
  return text;
}

std::string full_request(std::uint16_t port, const std::string& extra_headers = "") {
  return "GET / HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) + "\r\n" + extra_headers + "\r\n";
}

// A keep-alive (`{}` data: never locks the source) padded with JSON whitespace to `bytes`.
std::string keep_alive_of_size(std::size_t bytes) {
  const std::string head = R"({"name":"ocp_client_user_data","data":{})";
  return head + std::string(bytes - head.size() - 1, ' ') + "}";
}

class WebviewHostile : public ::testing::Test {
 protected:
  void start(WebviewLimits limits = {}, std::vector<std::string> allowed_origins = {}) {
    WebviewOptions options;
    options.port = 0;
    options.root = root_.root;
    options.limits = limits;
    options.allowed_origins = std::move(allowed_origins);
    server_ = std::make_unique<WebviewServer>(executor_, options, Logger(executor_, "player:webview", log_.sink()));
    ASSERT_TRUE(server_->listen().ok());
    port_ = server_->port();
  }
  void TearDown() override {
    if (server_) server_->stop();
  }
  std::size_t log_lines_with(const std::string& needle) const {
    const auto& lines = log_.lines();
    return static_cast<std::size_t>(std::count_if(lines.begin(), lines.end(), [&](const CapturedLog::Line& line) {
      return line.message.find(needle) != std::string::npos;
    }));
  }
  // Lines that open a refusal episode (the episode's last line repeats the last detail).
  std::size_t episodes_opened_with(const std::string& needle) const {
    const auto& lines = log_.lines();
    return static_cast<std::size_t>(std::count_if(lines.begin(), lines.end(), [&](const CapturedLog::Line& line) {
      return line.message.find(needle) != std::string::npos &&
             line.message.find("(more of these are counted") != std::string::npos;
    }));
  }
  std::string own(const std::string& host = "127.0.0.1") const { return "http://" + host + ":" + std::to_string(port_); }
  const WebviewStats& stats() const { return server_->stats(); }

  boost::asio::io_context io_;
  AsioExecutor executor_{io_};
  CapturedLog log_;
  testing::TempWebRoot root_;
  std::unique_ptr<WebviewServer> server_;
  std::uint16_t port_ = 0;
};

// --- Origin and Host --------------------------------------------------------------------

TEST(WebviewOriginSyntax, OriginsAreCheckedAndNormalised) {
  const std::vector<std::pair<std::string, std::string>> good{
      {"http://localhost:8080", "http://localhost:8080"},
      {"HTTP://LocalHost:8080", "http://localhost:8080"},
      {"http://example.com:80", "http://example.com"},
      {"https://example.com:443", "https://example.com"},
      {"https://example.com:8443", "https://example.com:8443"},
      {"http://127.0.0.1:5173", "http://127.0.0.1:5173"},
      {"http://[::1]:8080", "http://[::1]:8080"},
      {"chrome-extension://abcdef", "chrome-extension://abcdef"},
  };
  for (const auto& [text, expected] : good) {
    const auto origin = parse_webview_origin(text);
    ASSERT_TRUE(origin.ok()) << text << ": " << origin.error().detail;
    EXPECT_EQ(*origin, expected) << text;
  }
  const std::vector<std::pair<std::string, std::string>> bad{
      {"localhost:8080", "no '://'"},
      {"http://localhost:8080/", "no path"},
      {"http://localhost:8080/app", "no path"},
      {"http://localhost?x=1", "no path"},
      {"http://user@localhost", "no user info"},
      {"http://", "no host"},
      {"http://:8080", "no host"},
      {"http://localhost:", "the port is a number"},
      {"http://localhost:0", "the port is a number"},
      {"http://localhost:65536", "the port is a number"},
      {"http://localhost:80a", "the port is a number"},
      {"http://exa mple.com", "the host is"},
      {"http://*", "the host is"},
      {"null", "no '://'"},
      {"", "no '://'"},
      {"1http://x", "the scheme"},
      {"://x", "the scheme"},
      {"http://[::1", "IPv6"},
  };
  for (const auto& [text, expected] : bad) {
    const auto origin = parse_webview_origin(text);
    ASSERT_FALSE(origin.ok()) << text;
    EXPECT_NE(origin.error().detail.find(expected), std::string::npos) << text << ": " << origin.error().detail;
    EXPECT_NE(origin.error().detail.find("'" + text + "'"), std::string::npos) << origin.error().detail;
  }
}

TEST_F(WebviewHostile, AForeignOriginGets403AndNoWebSocket) {
  start();
  const std::vector<std::string> origins{"http://evil.example", "null", "http://127.0.0.1:1",
                                        "https://127.0.0.1:" + std::to_string(port_)};
  for (const std::string& origin : origins) {
    WsClient page(io_);
    page.origin = origin;
    EXPECT_FALSE(page.connect(io_, port_)) << origin;
    EXPECT_EQ(page.handshake_status(), 403u) << origin;
  }
  EXPECT_EQ(stats().websocket_accepted, 0u);
  EXPECT_EQ(stats().origin_refused, 4u);
  EXPECT_EQ(server_->websocket_clients(), 0u);
  // A plain request from a foreign page too (a cross-origin fetch).
  EXPECT_EQ(testing::http_get(io_, port_, "/", {{"Origin", "http://evil.example"}}).status, 403u);
  EXPECT_EQ(testing::http_get(io_, port_, "/").status, 200u);   // curl: no Origin
}

TEST_F(WebviewHostile, AForeignHostGets421) {
  start();
  const std::string port = std::to_string(port_);
  // evil.example resolving to 127.0.0.1 (DNS rebinding): the page's origin is then its own.
  const std::vector<std::string> hosts{"evil.example:" + port, "127.0.0.1", "localhost:1", "127.0.0.2:" + port};
  for (const std::string& host : hosts) {
    WsClient page(io_);
    page.host = host;
    page.origin = "http://" + host;
    EXPECT_FALSE(page.connect(io_, port_)) << host;
    EXPECT_EQ(page.handshake_status(), 421u) << host;
  }
  EXPECT_EQ(testing::http_get(io_, port_, "/", {{"Host", "evil.example:" + port}}).status, 421u);
  EXPECT_EQ(stats().host_refused, 5u);
  EXPECT_EQ(stats().websocket_accepted, 0u);
}

TEST_F(WebviewHostile, TheWebviewsOwnOriginsAndClientsWithoutOriginConnect) {
  start();
  WsClient numeric(io_), named(io_), bare(io_), shouting(io_);
  numeric.origin = own();
  named.host = "localhost:" + std::to_string(port_);
  named.origin = own("localhost");
  shouting.host = "LOCALHOST:" + std::to_string(port_);
  shouting.origin = "HTTP://LocalHost:" + std::to_string(port_);
  for (WsClient* page : {&numeric, &named, &bare, &shouting}) {
    EXPECT_TRUE(page->connect(io_, port_)) << page->origin;
    EXPECT_EQ(page->handshake_status(), 101u) << page->origin;
  }
  EXPECT_EQ(stats().websocket_accepted, 4u);
  EXPECT_EQ(testing::http_get(io_, port_, "/", {{"Origin", own()}}).status, 200u);
}

TEST_F(WebviewHostile, WithRemoteAccessTheAddressAConnectionCameToIsItsOwnHost) {
  WebviewOptions options;
  options.port = 0;
  options.allow_remote = true;   // 0.0.0.0: 127.0.0.2 stands for the machine's LAN address here
  options.root = root_.root;
  server_ = std::make_unique<WebviewServer>(executor_, options, Logger(executor_, "player:webview", log_.sink()));
  ASSERT_TRUE(server_->listen().ok());
  port_ = server_->port();
  WsClient remote(io_), rebound(io_), crossed(io_);
  remote.address = "127.0.0.2";   // Host 127.0.0.2:PORT, as a browser elsewhere sends it
  remote.origin = "http://127.0.0.2:" + std::to_string(port_);
  EXPECT_TRUE(remote.connect(io_, port_));
  EXPECT_EQ(remote.handshake_status(), 101u);
  rebound.address = "127.0.0.2";
  rebound.host = "evil.example:" + std::to_string(port_);
  EXPECT_FALSE(rebound.connect(io_, port_));
  EXPECT_EQ(rebound.handshake_status(), 421u);
  crossed.address = "127.0.0.2";   // a Host naming another address of the machine is not this connection's
  crossed.host = "127.0.0.3:" + std::to_string(port_);
  EXPECT_FALSE(crossed.connect(io_, port_));
  EXPECT_EQ(crossed.handshake_status(), 421u);
}

TEST_F(WebviewHostile, AnAllowedOriginConnectsAndOnlyThatOne) {
  start({}, {"http://localhost:8080", "HTTPS://Tools.Example"});
  WsClient allowed(io_), secure(io_), other_port(io_);
  allowed.origin = "http://localhost:8080";
  secure.origin = "https://tools.example";
  other_port.origin = "http://localhost:8081";
  EXPECT_TRUE(allowed.connect(io_, port_));
  EXPECT_EQ(allowed.handshake_status(), 101u);
  EXPECT_TRUE(secure.connect(io_, port_));
  EXPECT_FALSE(other_port.connect(io_, port_));
  EXPECT_EQ(other_port.handshake_status(), 403u);
}

TEST_F(WebviewHostile, AMalformedAllowedOriginFailsListen) {
  WebviewOptions options;
  options.port = 0;
  options.root = root_.root;
  options.allowed_origins = {"http://localhost:8080/"};
  WebviewServer server(executor_, options, Logger(executor_, "player:webview", log_.sink()));
  const Status status = server.listen();
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.error().detail.find("no path"), std::string::npos) << status.error().detail;
}

TEST_F(WebviewHostile, RefusalsAreLoggedOncePerEpisodeWithACount) {
  WebviewLimits limits;
  limits.refusal_episode_gap = 2s;
  start(limits);
  for (int i = 0; i < 5; ++i) {
    WsClient page(io_);
    page.origin = "http://evil.example";
    EXPECT_FALSE(page.connect(io_, port_));
  }
  EXPECT_EQ(episodes_opened_with("Origin 'http://evil.example' is not this web view's"), 1u);
  ASSERT_TRUE(run_until(io_, [&] { return log_.contains("5 requests from a foreign Origin refused (403) in"); }));
  // The next attack is a new episode: it is reported again.
  WsClient again(io_);
  again.origin = "http://evil.example";
  EXPECT_FALSE(again.connect(io_, port_));
  EXPECT_EQ(episodes_opened_with("Origin 'http://evil.example' is not this web view's"), 2u);
  EXPECT_EQ(log_lines_with("foreign Origin refused"), 1u);   // a single refusal needs no count line
}

// --- Message size -------------------------------------------------------------------------

TEST_F(WebviewHostile, MessagesOf36To63KiBInOneFrameAreTakenIn) {
  start();
  WsClient page(io_);
  ASSERT_TRUE(page.connect(io_, port_));
  // Each counted once, however the reads cut it (counting the buffer on every read made
  // 36 KiB anything from 60 to 84 KiB, depending on how the bytes arrived).
  const std::vector<std::size_t> sizes{36 * 1024, 48 * 1024, 63 * 1024};
  for (const std::size_t size : sizes) page.send(keep_alive_of_size(size));
  ASSERT_TRUE(run_until(io_, [&] { return stats().keep_alives + stats().messages_dropped >= sizes.size(); }));
  EXPECT_EQ(stats().keep_alives, sizes.size());
  EXPECT_EQ(stats().messages_dropped, 0u);
  EXPECT_FALSE(page.closed());
}

TEST_F(WebviewHostile, A9KiBMessageIn1KiBFragmentsIsTakenIn) {
  start();
  WsClient page(io_);
  ASSERT_TRUE(page.connect(io_, port_));
  page.send(keep_alive_of_size(9 * 1024), false, 1024);
  ASSERT_TRUE(run_until(io_, [&] { return stats().keep_alives + stats().messages_dropped >= 1; }));
  EXPECT_EQ(stats().keep_alives, 1u);
  EXPECT_EQ(stats().messages_dropped, 0u);
  EXPECT_FALSE(log_.contains("bytes, limit"));
}

TEST_F(WebviewHostile, AMessageOfExactlyTheLimitIsTakenInOneByteMoreClosesWith1009) {
  start();
  WsClient page(io_);
  ASSERT_TRUE(page.connect(io_, port_));
  page.send(keep_alive_of_size(webview::max_message_bytes), false, 4096);
  ASSERT_TRUE(run_until(io_, [&] { return stats().keep_alives == 1; }));
  page.send(keep_alive_of_size(webview::max_message_bytes + 1));
  ASSERT_TRUE(run_until(io_, [&] { return page.closed(); }));
  EXPECT_EQ(page.close_code(), 1009u);
  EXPECT_EQ(stats().keep_alives, 1u);
  EXPECT_EQ(stats().messages_dropped, 1u);
  EXPECT_EQ(log_lines_with("a message over 65536 bytes; closed with 1009 (message too big)"), 1u);
  ASSERT_TRUE(run_until(io_, [&] { return server_->websocket_clients() == 0; }));
}

TEST_F(WebviewHostile, AnOversizedMessageInSmallFragmentsClosesWith1009) {
  start();
  WsClient page(io_);
  ASSERT_TRUE(page.connect(io_, port_));
  page.send(keep_alive_of_size(65 * 1024 + 1), false, 1024);
  ASSERT_TRUE(run_until(io_, [&] { return page.closed(); }));
  EXPECT_EQ(page.close_code(), 1009u);
  EXPECT_EQ(stats().keep_alives, 0u);
}

// --- Slowloris, header limits, per-address quota ---------------------------------------------

// A reconnecting slowloris: connections that each trickle an endless request and, when the
// server closes one, open a new one `reconnect_delay` later.
class Slowloris {
 public:
  Slowloris(boost::asio::io_context& io, std::uint16_t port, std::size_t count, std::chrono::milliseconds reconnect_delay)
      : io_(io), port_(port), reconnect_delay_(reconnect_delay), peers_(count) {
    for (std::size_t index = 0; index < count; ++index) open(index);
  }
  std::size_t reopened() const { return reopened_; }
  std::size_t open_count() const {
    return static_cast<std::size_t>(std::count_if(peers_.begin(), peers_.end(), [](const auto& peer) {
      return peer->connected() && !peer->closed_by_server();
    }));
  }

 private:
  void open(std::size_t index) {
    if (peers_[index]) closed_.push_back(std::move(peers_[index]));   // its handlers may still be queued
    auto& peer = peers_[index] = std::make_unique<RawPeer>(io_);
    peer->on_closed = [this, index] {
      auto timer = std::make_shared<boost::asio::steady_timer>(io_, reconnect_delay_);
      timer->async_wait([this, index, timer, alive = std::weak_ptr<int>(alive_)](boost::system::error_code error) {
        if (error || !alive.lock()) return;
        ++reopened_;
        open(index);
      });
    };
    if (peer->connect(port_)) peer->trickle(endless_request(port_), 50ms);
  }

  boost::asio::io_context& io_;
  std::uint16_t port_;
  std::chrono::milliseconds reconnect_delay_;
  std::vector<std::unique_ptr<RawPeer>> peers_;
  std::vector<std::unique_ptr<RawPeer>> closed_;
  std::size_t reopened_ = 0;
  std::shared_ptr<int> alive_ = std::make_shared<int>(0);   // a reconnect timer outliving this does nothing
};

TEST_F(WebviewHostile, ReconnectingSlowlorisConnectionsHoldingEverySlotDoNotStopGoodRequests) {
  WebviewLimits limits;
  limits.max_http_connections = 8;
  limits.max_connections_per_address = 1000;   // all from 127.0.0.1 here: slots and reclaiming are tested
  limits.header_idle_timeout = 30s;            // no timeout frees a slot within the test
  limits.header_timeout = 60s;
  start(limits);
  {
    Slowloris attack(io_, port_, 8, 5ms);
    ASSERT_TRUE(run_until(io_, [&] { return attack.open_count() == 8 && server_->http_connections() == 8; }));
    // Every good request is served at its first try while the attacker holds every slot and
    // reopens what is closed within 5 ms.
    const auto begin = std::chrono::steady_clock::now();
    std::vector<unsigned> statuses;
    for (int i = 0; i < 10; ++i) {
      // The attacker is back at full strength (and the last good connection is gone).
      ASSERT_TRUE(run_until(io_, [&] { return attack.open_count() == 8 && server_->http_connections() == 8; }));
      statuses.push_back(testing::http_get(io_, port_, "/").status);
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    std::printf("10 good GETs in %.3f s against 8 reconnecting slowloris connections: %zu reclaimed, %zu reopened\n",
                seconds, static_cast<std::size_t>(stats().connections_reclaimed), attack.reopened());
    EXPECT_EQ(statuses, std::vector<unsigned>(10, 200u));
    EXPECT_GE(stats().connections_reclaimed, 10u);
    EXPECT_GE(attack.reopened(), 9u);   // each reclaimed connection reopened (the last one may still be on its way)
    EXPECT_EQ(stats().request_timeouts, 0u);
    EXPECT_EQ(episodes_opened_with("to make room for 127.0.0.1"), 1u);   // once per episode
    server_->stop();   // before the attacker goes: its reconnects then fail
  }
}

TEST_F(WebviewHostile, ATricklingRequestIsClosedAtItsDeadlineASilentOneAfterTheIdleTimeout) {
  WebviewLimits limits;
  limits.header_timeout = 1800ms;
  limits.header_idle_timeout = 600ms;   // 12 trickled bytes apart: a loaded machine keeps it busy
  limits.refusal_episode_gap = 2500ms;   // both timeouts, 1.2 s apart, are one episode
  start(limits);
  const auto begin = std::chrono::steady_clock::now();
  const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count(); };
  RawPeer trickler(io_), stalled(io_), silent(io_);
  ASSERT_TRUE(trickler.connect(port_));
  trickler.trickle(endless_request(port_), 50ms);   // a byte every 50 ms: never idle
  ASSERT_TRUE(stalled.connect(port_));
  stalled.write("GET / HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port_) + "\r\n");
  ASSERT_TRUE(silent.connect(port_));
  double stalled_at = 0, silent_at = 0, trickler_at = 0;
  ASSERT_TRUE(run_until(io_, [&] {
    if (stalled.closed_by_server() && stalled_at == 0) stalled_at = elapsed();
    if (silent.closed_by_server() && silent_at == 0) silent_at = elapsed();
    if (trickler.closed_by_server() && trickler_at == 0) trickler_at = elapsed();
    return stalled_at > 0 && silent_at > 0 && trickler_at > 0;
  }, 10s));
  std::printf("closed after: silent %.2f s, stalled %.2f s, trickling %.2f s\n", silent_at, stalled_at, trickler_at);
  EXPECT_GE(stalled_at, 0.55);
  EXPECT_LT(stalled_at, 1.7);     // the idle timeout, not the deadline, closed it
  EXPECT_GE(silent_at, 0.55);
  EXPECT_GE(trickler_at, 1.75);   // the deadline, not the idle timeout, closed it
  EXPECT_LT(trickler_at, 6.0);
  EXPECT_EQ(stats().request_timeouts, 2u);   // a connection that never sent a byte is only idle
  EXPECT_EQ(episodes_opened_with("its request was not complete"), 1u);
  ASSERT_TRUE(run_until(io_, [&] { return log_.contains("2 connections closed: request not complete in time"); }));
  EXPECT_EQ(server_->http_connections(), 0u);
}

TEST_F(WebviewHostile, AHeaderOver8KiBGets431) {
  start();
  RawPeer peer(io_);
  ASSERT_TRUE(peer.connect(port_));
  peer.write(full_request(port_, "X-Big: " + std::string(9 * 1024, 'b') + "\r\n"));
  ASSERT_TRUE(run_until(io_, [&] { return peer.closed_by_server(); }));
  EXPECT_EQ(peer.status(), 431u) << peer.received();
  EXPECT_EQ(stats().headers_too_large, 1u);
  // Just under the limit is served.
  RawPeer fits(io_);
  ASSERT_TRUE(fits.connect(port_));
  fits.write(full_request(port_, "X-Big: " + std::string(7 * 1024, 'b') + "\r\nConnection: close\r\n"));
  ASSERT_TRUE(run_until(io_, [&] { return fits.closed_by_server(); }));
  EXPECT_EQ(fits.status(), 200u);
  EXPECT_EQ(server_->http_connections(), 0u);
}

TEST_F(WebviewHostile, OverThePerAddressLimitGets503AndHoldsNoSlot) {
  WebviewLimits limits;
  limits.max_connections_per_address = 4;
  limits.stalled_after = 60s;   // nothing is reclaimable: the limit alone answers
  limits.header_idle_timeout = 60s;
  limits.header_timeout = 60s;
  start(limits);
  // 127.0.0.2 is another remote address to the server (all of 127/8 is loopback).
  std::vector<std::unique_ptr<RawPeer>> holders;
  for (int i = 0; i < 4; ++i) {
    holders.push_back(std::make_unique<RawPeer>(io_));
    ASSERT_TRUE(holders.back()->connect(port_, "127.0.0.2"));
    holders.back()->write("GET / HTTP/1.1\r\n");
  }
  ASSERT_TRUE(run_until(io_, [&] { return server_->http_connections() == 4; }));
  RawPeer over(io_);
  ASSERT_TRUE(over.connect(port_, "127.0.0.2"));
  over.write(full_request(port_));
  const auto begin = std::chrono::steady_clock::now();
  ASSERT_TRUE(run_until(io_, [&] { return over.closed_by_server(); }));
  const double closed_after = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  std::printf("503 answered and closed after %.3f s\n", closed_after);
  EXPECT_EQ(over.status(), 503u) << over.received();
  EXPECT_NE(over.received().find("Connection: close"), std::string::npos);
  EXPECT_EQ(stats().connections_refused, 1u);
  EXPECT_EQ(server_->http_connections(), 4u);   // the refused connection never held a slot
  EXPECT_EQ(episodes_opened_with("4 connections from that address already open"), 1u);
  // Another address is served meanwhile.
  EXPECT_EQ(testing::http_get(io_, port_, "/").status, 200u);
  // A holder that goes frees its slot for its address.
  holders.front()->close();
  ASSERT_TRUE(run_until(io_, [&] { return server_->http_connections() == 3; }));
  RawPeer next(io_);
  ASSERT_TRUE(next.connect(port_, "127.0.0.2"));
  next.write(full_request(port_, "Connection: close\r\n"));
  ASSERT_TRUE(run_until(io_, [&] { return next.closed_by_server(); }));
  EXPECT_EQ(next.status(), 200u);
}

TEST_F(WebviewHostile, AWebSocketRefusedForTooManyClientsIsClosedAtOnce) {
  WebviewLimits limits;
  limits.max_clients = 1;
  limits.header_idle_timeout = 60s;
  start(limits);
  WsClient first(io_), second(io_);
  ASSERT_TRUE(first.connect(io_, port_));
  EXPECT_FALSE(second.connect(io_, port_));
  EXPECT_EQ(second.handshake_status(), 503u);
  // Its HTTP slot is free at once, not after an idle keep-alive.
  ASSERT_TRUE(run_until(io_, [&] { return server_->http_connections() == 0; }));
}

}  // namespace
}  // namespace ocp
