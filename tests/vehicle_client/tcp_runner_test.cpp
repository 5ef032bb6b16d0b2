// The real-time TCP side over loopback, against a minimal framed server in the test (a TcpTestServer
// of StreamerPeers on an ephemeral port). Bounds are generous: nothing here may flake on a
// loaded 2-core machine; time limits are only upper bounds for "it eventually happened".
#include "vehicle_app/tcp_runner.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <boost/asio/io_context.hpp>
#include <memory>
#include <vector>

#include "ocp/asio/executor.hpp"
#include "ocp/asio/tcp_server.hpp"
#include "streamer_peer.hpp"
#include "tcp_peers.hpp"

namespace ocp {
namespace {

using testing::StreamerPeer;
using StreamerServer = testing::TcpTestServer<StreamerPeer>;

struct LoopbackWorld {
  LoopbackWorld() {
    client = std::make_unique<VehicleClient>(executor, VehicleClientConfig{},
                                             Logger(executor, "vehicle-client", make_null_sink()));
  }

  std::unique_ptr<TcpRunner> make_runner(std::uint16_t port, Micros connect_timeout = Micros{2'000'000}) {
    TcpRunnerConfig config;
    config.server = Endpoint{"127.0.0.1", port};
    config.connect_timeout = connect_timeout;
    config.backoff_initial = Micros{20'000};
    config.backoff_max = Micros{80'000};
    auto runner = std::make_unique<TcpRunner>(executor, *client, config,
                                              Logger(executor, "tcp", make_null_sink()));
    runner->set_on_event([this](const RunnerConnectionEvent& event) { events.push_back(event); });
    return runner;
  }

  // A Streamer peer for every accepted connection, optionally sending one control message first.
  std::unique_ptr<StreamerServer> make_server(bool send_first_control) {
    auto server = std::make_unique<StreamerServer>(io, [this] { return std::make_unique<StreamerPeer>(executor); });
    if (send_first_control) {
      server->on_accept = [](StreamerPeer& streamer) { streamer.send_control(OcpControlMessage{}); };
    }
    return server;
  }

  std::size_t count(ConnectionEventKind kind) const {
    std::size_t total = 0;
    for (const auto& event : events) total += event.kind == kind ? 1 : 0;
    return total;
  }

  boost::asio::io_context io;
  AsioExecutor executor{io};
  std::unique_ptr<VehicleClient> client;
  std::vector<RunnerConnectionEvent> events;
};

TEST(VehicleClientTcp, ConnectsAndEchoesOverLoopback) {
  LoopbackWorld world;
  auto server = world.make_server(/*send_first_control=*/true);
  ASSERT_TRUE(server->listen().ok());
  auto runner = world.make_runner(server->port());
  runner->start();

  ASSERT_TRUE(testing::run_until(world.io, [&] {
    return server->accepted() >= 1 && !server->peer(0).responses.empty();
  }));
  StreamerPeer& streamer = server->peer(0);
  EXPECT_EQ(streamer.responses[0].message.ack, streamer.sent[0].ack);
  EXPECT_TRUE(streamer.verify(streamer.responses[0].message.ack));
  EXPECT_EQ(world.count(ConnectionEventKind::connected), 1u);
  EXPECT_TRUE(world.client->connected());
  runner->stop();
  EXPECT_FALSE(world.client->connected());
}

TEST(VehicleClientTcp, RetriesWithGrowingBackoffWhileRefusedThenConnects) {
  LoopbackWorld world;
  std::uint16_t port = 0;
  {
    TcpServer probe(world.io, [](std::shared_ptr<ByteStream>) {});
    ASSERT_TRUE(probe.listen({}).ok());
    port = probe.port();
  }  // closed again: connecting to `port` is now refused
  auto runner = world.make_runner(port);
  runner->start();
  ASSERT_TRUE(testing::run_until(world.io, [&] { return world.count(ConnectionEventKind::retry_scheduled) >= 5; }));

  std::vector<std::int64_t> delays_ms;
  for (const auto& event : world.events) {
    if (event.kind == ConnectionEventKind::retry_scheduled) delays_ms.push_back(to_whole_ms(event.retry_in));
  }
  EXPECT_EQ(std::vector<std::int64_t>(delays_ms.begin(), delays_ms.begin() + 5),
            (std::vector<std::int64_t>{20, 40, 80, 80, 80}));
  EXPECT_GE(runner->stats().refused, 5u);
  for (const auto& event : world.events) {
    if (event.kind == ConnectionEventKind::refused) {
      EXPECT_NE(event.detail.find("refused"), std::string::npos);
    }
  }

  // The Streamer comes up on that port: the next retry connects.
  auto server = world.make_server(/*send_first_control=*/false);
  ASSERT_TRUE(server->listen(port).ok());
  ASSERT_TRUE(testing::run_until(world.io, [&] { return world.client->connected(); }));
  EXPECT_EQ(runner->stats().connections, 1u);
}

TEST(VehicleClientTcp, ReconnectsAfterTheServerDropsTheConnection) {
  LoopbackWorld world;
  auto server = world.make_server(/*send_first_control=*/true);
  ASSERT_TRUE(server->listen().ok());
  auto runner = world.make_runner(server->port());
  runner->start();
  ASSERT_TRUE(testing::run_until(world.io, [&] {
    return server->accepted() >= 1 && !server->peer(0).responses.empty();
  }));
  server->peer(0).close();
  ASSERT_TRUE(testing::run_until(world.io, [&] {
    return server->accepted() >= 2 && !server->peer(1).responses.empty();
  }));
  EXPECT_EQ(world.count(ConnectionEventKind::disconnected), 1u);
  EXPECT_EQ(runner->stats().connections, 2u);
  // The dropped session carried control messages, so the backoff started over.
  EXPECT_EQ(world.events[world.events.size() - 3].kind, ConnectionEventKind::retry_scheduled);
  EXPECT_EQ(runner->current_backoff(), Micros{40'000});
}

TEST(VehicleClientTcp, SaysNotAnOcpServerWhenThePeerSpeaksSomethingElse) {
  LoopbackWorld world;
  testing::TcpTestServer<> server(world.io);
  server.on_accept = [](testing::FramedPeer& peer) {
    peer.send_raw("HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\n\r\n");
  };
  ASSERT_TRUE(server.listen().ok());
  auto runner = world.make_runner(server.port());
  runner->start();
  ASSERT_TRUE(testing::run_until(world.io, [&] { return world.count(ConnectionEventKind::not_an_ocp_server) >= 1; }));
  const auto event = std::find_if(world.events.begin(), world.events.end(), [](const RunnerConnectionEvent& e) {
    return e.kind == ConnectionEventKind::not_an_ocp_server;
  });
  EXPECT_NE(event->detail.find("not an OCP server"), std::string::npos) << event->detail;
  EXPECT_EQ(runner->stats().not_an_ocp_server, 1u);
  EXPECT_EQ(world.count(ConnectionEventKind::disconnected), 0u);
}

// Linux drops the SYN of a connection to a listener whose accept queue is full, so a connect
// to it stays unanswered: a deterministic way to make a loopback connect time out.
TEST(VehicleClientTcp, SaysTimedOutWhenTheServerNeverAnswersTheConnect) {
  LoopbackWorld world;
  namespace asio = boost::asio;
  asio::ip::tcp::acceptor unanswering(world.io, asio::ip::tcp::endpoint(asio::ip::address_v4::loopback(), 0));
  unanswering.listen(0);  // a backlog of 0 still queues one connection...
  asio::ip::tcp::socket queued(world.io);
  queued.connect(unanswering.local_endpoint());  // ...this one, never accepted: the queue is full
  auto runner = world.make_runner(unanswering.local_endpoint().port(), Micros{150'000});
  runner->start();
  ASSERT_TRUE(testing::run_until(world.io, [&] { return world.count(ConnectionEventKind::timed_out) >= 1; }));
  const auto event = std::find_if(world.events.begin(), world.events.end(), [](const RunnerConnectionEvent& e) {
    return e.kind == ConnectionEventKind::timed_out;
  });
  EXPECT_NE(event->detail.find("timed out after 150 ms"), std::string::npos) << event->detail;
  EXPECT_EQ(runner->stats().timed_out, 1u);
  EXPECT_FALSE(world.client->connected());
  // A timed-out attempt is retried like a refused one.
  ASSERT_TRUE(testing::run_until(world.io, [&] { return world.count(ConnectionEventKind::retry_scheduled) >= 1; }));
  runner->stop();
}

TEST(VehicleClientTcp, StopCancelsThePendingRetry) {
  LoopbackWorld world;
  std::uint16_t port = 0;
  {
    TcpServer probe(world.io, [](std::shared_ptr<ByteStream>) {});
    ASSERT_TRUE(probe.listen({}).ok());
    port = probe.port();
  }
  auto runner = world.make_runner(port);
  runner->start();
  ASSERT_TRUE(testing::run_until(world.io, [&] { return world.count(ConnectionEventKind::retry_scheduled) >= 1; }));
  runner->stop();
  const std::uint64_t attempts = runner->stats().attempts;
  testing::run_for(world.io, std::chrono::milliseconds(200));
  EXPECT_EQ(runner->stats().attempts, attempts);
  EXPECT_FALSE(runner->running());
  EXPECT_EQ(world.events.back().kind, ConnectionEventKind::stopped);
}

TEST(VehicleClientEndpoint, ParsesHostAndPort) {
  const Result<Endpoint> full = parse_endpoint("10.0.0.7:4100");
  ASSERT_TRUE(full.ok());
  EXPECT_EQ(full->host, "10.0.0.7");
  EXPECT_EQ(full->port, 4100);
  const Result<Endpoint> host_only = parse_endpoint("streamer.local");
  ASSERT_TRUE(host_only.ok());
  EXPECT_EQ(host_only->port, 4000);
  const Result<Endpoint> port_only = parse_endpoint(":4200");
  ASSERT_TRUE(port_only.ok());
  EXPECT_EQ(port_only->host, "127.0.0.1");
  EXPECT_EQ(port_only->port, 4200);
  const Result<Endpoint> v6 = parse_endpoint("[::1]:4000");
  ASSERT_TRUE(v6.ok());
  EXPECT_EQ(v6->host, "::1");
}

TEST(VehicleClientEndpoint, RejectsBadEndpointsWithAReason) {
  for (const char* text : {"host:", "host:0", "host:65536", "host:40x0", "::1:4000", "[::1", "[::1]x"}) {
    const Result<Endpoint> endpoint = parse_endpoint(text);
    EXPECT_FALSE(endpoint.ok()) << text;
    if (!endpoint.ok()) {
      EXPECT_NE(endpoint.error().detail.find(text), std::string::npos);
    }
  }
}

}  // namespace
}  // namespace ocp
