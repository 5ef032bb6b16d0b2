// TcpServer on real loopback sockets: ephemeral ports, accepted streams, clear bind errors.
#include "ocp/asio/tcp_server.hpp"

#include <gtest/gtest.h>

#include <boost/asio/io_context.hpp>
#include <memory>
#include <string>
#include <vector>

#include "tcp_peers.hpp"

namespace ocp {
namespace {

using TcpClient = testing::TcpTestClient<>;
using testing::run_until;

struct AcceptedStreams {
  std::vector<std::shared_ptr<ByteStream>> streams;
  std::string received;
  TcpServer::AcceptHandler handler() {
    return [this](std::shared_ptr<ByteStream> stream) {
      stream->set_handlers({[this](std::string_view bytes) { received.append(bytes); }, {}});
      streams.push_back(std::move(stream));
    };
  }
};

TEST(TcpServer, PortZeroBindsAnEphemeralLoopbackPort) {
  boost::asio::io_context io;
  AcceptedStreams accepted;
  TcpServer server(io, accepted.handler());
  ASSERT_TRUE(server.listen({.port = 0}).ok());
  EXPECT_TRUE(server.listening());
  EXPECT_NE(server.port(), 0);
  EXPECT_EQ(server.local_address(), "127.0.0.1:" + std::to_string(server.port()));
}

TEST(TcpServer, AcceptedConnectionBecomesAByteStreamCarryingBytesBothWays) {
  boost::asio::io_context io;
  AcceptedStreams accepted;
  TcpServer server(io, accepted.handler());
  ASSERT_TRUE(server.listen({.port = 0}).ok());

  TcpClient client(io);
  ASSERT_TRUE(client.connect(server.port())) << client.connect_error();
  ASSERT_TRUE(run_until(io, [&] { return accepted.streams.size() == 1; }));
  EXPECT_EQ(server.accepted_count(), 1u);
  EXPECT_NE(accepted.streams[0]->peer_name().find("127.0.0.1:"), std::string::npos);

  client.send_payload(R"({"hello":1})");
  ASSERT_TRUE(run_until(io, [&] { return accepted.received.size() == 4 + 11; }));
  EXPECT_EQ(accepted.received.substr(4), R"({"hello":1})");

  accepted.streams[0]->write(testing::frame_of(R"({"back":2})"));
  ASSERT_TRUE(run_until(io, [&] { return client.frames().size() == 1; }));
  EXPECT_EQ(client.frames()[0].payload, R"({"back":2})");
}

TEST(TcpServer, EveryConnectionIsHandedOverIncludingConcurrentOnes) {
  boost::asio::io_context io;
  AcceptedStreams accepted;
  TcpServer server(io, accepted.handler());
  ASSERT_TRUE(server.listen({.port = 0}).ok());

  TcpClient first(io);
  TcpClient second(io);
  ASSERT_TRUE(first.connect(server.port()));
  ASSERT_TRUE(second.connect(server.port()));
  // The server only accepts; refusing a second vehicle is the core's job.
  ASSERT_TRUE(run_until(io, [&] { return accepted.streams.size() == 2; }));
}

TEST(TcpServer, PortInUseIsAClearError) {
  boost::asio::io_context io;
  AcceptedStreams accepted;
  TcpServer first(io, accepted.handler());
  ASSERT_TRUE(first.listen({.port = 0}).ok());

  TcpServer second(io, accepted.handler());
  const Status status = second.listen({.port = first.port()});
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().code, std::errc::address_in_use);
  EXPECT_EQ(status.error().detail, "another socket listens on 127.0.0.1:" + std::to_string(first.port()));
  // Said once (issue #19 item 8: "Address already in use: address … already in use").
  EXPECT_EQ(status.error().message(),
            "Address already in use: another socket listens on 127.0.0.1:" + std::to_string(first.port()));
  EXPECT_FALSE(second.listening());
  EXPECT_EQ(second.port(), 0);
}

TEST(TcpServer, StopRefusesNewConnectionsAndTheSamePortCanBeListenedOnAgain) {
  boost::asio::io_context io;
  AcceptedStreams accepted;
  TcpServer server(io, accepted.handler());
  ASSERT_TRUE(server.listen({.port = 0}).ok());
  const std::uint16_t port = server.port();

  // A connection that was accepted keeps working across stop(), and leaves the port in
  // use by an established socket (SO_REUSEADDR must let us listen again).
  TcpClient client(io);
  ASSERT_TRUE(client.connect(port));
  ASSERT_TRUE(run_until(io, [&] { return accepted.streams.size() == 1; }));

  server.stop();
  server.stop();  // idempotent
  EXPECT_FALSE(server.listening());
  TcpClient refused(io);
  EXPECT_FALSE(refused.connect(port));

  ASSERT_TRUE(server.listen({.port = port}).ok());
  EXPECT_EQ(server.port(), port);
  TcpClient again(io);
  ASSERT_TRUE(again.connect(port));
  ASSERT_TRUE(run_until(io, [&] { return accepted.streams.size() == 2; }));
}

TEST(TcpServer, AllowRemoteBindsAllInterfaces) {
  boost::asio::io_context io;
  AcceptedStreams accepted;
  TcpServer server(io, accepted.handler());
  ASSERT_TRUE(server.listen({.port = 0, .allow_remote = true}).ok());
  EXPECT_EQ(server.local_address(), "0.0.0.0:" + std::to_string(server.port()));
  TcpClient client(io);
  ASSERT_TRUE(client.connect(server.port()));
  ASSERT_TRUE(run_until(io, [&] { return accepted.streams.size() == 1; }));
}

TEST(TcpServer, DestroyedServerWithPendingAcceptIsSafe) {
  boost::asio::io_context io;
  int accepted = 0;
  {
    TcpServer server(io, [&](std::shared_ptr<ByteStream>) { ++accepted; });
    ASSERT_TRUE(server.listen({.port = 0}).ok());
  }
  // The aborted accept handler runs after the server is gone; it must not touch it.
  io.run();
  EXPECT_EQ(accepted, 0);
}

TEST(TcpServer, ListenAddressNamesTheBindAddress) {
  EXPECT_EQ(listen_address({.port = 4000}), "127.0.0.1:4000");
  EXPECT_EQ(listen_address({.port = 4001, .allow_remote = true}), "0.0.0.0:4001");
}

}  // namespace
}  // namespace ocp
