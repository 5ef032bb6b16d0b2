#include <gtest/gtest.h>

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <array>
#include <chrono>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "ocp/asio/tcp_stream.hpp"
#include "tcp_peers.hpp"

namespace ocp {
namespace {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;

// Generous: these run on a loaded 2-core machine.
constexpr std::chrono::milliseconds wait_limit{20'000};

// The shared bounded wait, with this suite's longer limit.
bool run_within_wait_limit(asio::io_context& io, const std::function<bool()>& done) {
  return testing::run_until(io, done, wait_limit);
}

struct Received {
  std::string bytes;
  std::vector<std::string> closes;
  ByteStreamHandlers handlers() {
    return ByteStreamHandlers{[this](std::string_view chunk) { bytes.append(chunk); },
                              [this](const std::string& reason) { closes.push_back(reason); }};
  }
};

// A connected pair of TCP streams over loopback.
struct Connection {
  asio::io_context io;
  std::shared_ptr<ByteStream> server;
  std::shared_ptr<ByteStream> client;

  Connection() {
    tcp::acceptor acceptor(io, tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0));
    tcp::socket server_socket(io);
    bool accepted = false;
    acceptor.async_accept(server_socket, [&](const boost::system::error_code& error) { accepted = !error; });
    tcp::socket client_socket(io);
    bool connected = false;
    client_socket.async_connect(acceptor.local_endpoint(), [&](const boost::system::error_code& error) { connected = !error; });
    run_within_wait_limit(io, [&] { return accepted && connected; });
    server = make_tcp_stream(std::move(server_socket));
    client = make_tcp_stream(std::move(client_socket));
  }
};

TEST(TcpStream, BytesFlowBothWays) {
  Connection connection;
  Received at_server;
  Received at_client;
  connection.server->set_handlers(at_server.handlers());
  connection.client->set_handlers(at_client.handlers());
  connection.client->write("hello ");
  connection.client->write("server");
  connection.server->write("hello client");
  ASSERT_TRUE(run_within_wait_limit(connection.io, [&] { return at_server.bytes.size() == 12 && at_client.bytes.size() == 12; }));
  EXPECT_EQ(at_server.bytes, "hello server");
  EXPECT_EQ(at_client.bytes, "hello client");
}

TEST(TcpStream, LargeWriteArrivesIntactAndInOrder) {
  Connection connection;
  Received at_server;
  connection.server->set_handlers(at_server.handlers());
  std::string big(1 << 20, '\0');
  for (std::size_t i = 0; i < big.size(); ++i) {
    big[i] = static_cast<char>((i * 131 + i / 977) & 0xff);
  }
  // Many writes queued at once, while one is in flight, must keep their order.
  connection.client->write(big.substr(0, 1000));
  for (std::size_t offset = 1000; offset < big.size(); offset += 65536) {
    connection.client->write(std::string_view(big).substr(offset, 65536));
  }
  ASSERT_TRUE(run_within_wait_limit(connection.io, [&] { return at_server.bytes.size() >= big.size(); }));
  EXPECT_TRUE(at_server.bytes == big);
}

TEST(TcpStream, BytesSentBeforeHandlersAreSetAreNotLost) {
  Connection connection;
  connection.client->write("early");
  // Give the bytes time to reach the server's kernel buffer before reading starts.
  const auto settle_until = std::chrono::steady_clock::now() + std::chrono::milliseconds(100);
  run_within_wait_limit(connection.io, [&] { return std::chrono::steady_clock::now() >= settle_until; });
  Received at_server;
  connection.server->set_handlers(at_server.handlers());
  ASSERT_TRUE(run_within_wait_limit(connection.io, [&] { return at_server.bytes == "early"; }));
}

TEST(TcpStream, PeerCloseIsReportedOnceAfterItsLastBytes) {
  Connection connection;
  Received at_server;
  Received at_client;
  connection.server->set_handlers(at_server.handlers());
  connection.client->set_handlers(at_client.handlers());
  connection.client->write("goodbye");
  connection.client->close();
  EXPECT_FALSE(connection.client->is_open());
  ASSERT_TRUE(run_within_wait_limit(connection.io, [&] { return !at_server.closes.empty(); }));
  EXPECT_EQ(at_server.bytes, "goodbye");
  ASSERT_EQ(at_server.closes.size(), 1u);
  EXPECT_EQ(at_server.closes[0], "connection closed by peer");
  EXPECT_FALSE(connection.server->is_open());
  EXPECT_TRUE(at_client.closes.empty());  // a local close is not reported locally
}

TEST(TcpStream, CloseIsIdempotentAndLaterWritesAreIgnored) {
  Connection connection;
  Received at_server;
  Received at_client;
  connection.server->set_handlers(at_server.handlers());
  connection.client->set_handlers(at_client.handlers());
  connection.client->close();
  connection.client->close();
  connection.client->write("ignored");
  ASSERT_TRUE(run_within_wait_limit(connection.io, [&] { return !at_server.closes.empty(); }));
  EXPECT_TRUE(at_server.bytes.empty());
  EXPECT_EQ(at_server.closes.size(), 1u);
  EXPECT_TRUE(at_client.closes.empty());
}

TEST(TcpStream, StreamStaysAliveWhileOperationsArePending) {
  Connection connection;
  Received at_server;
  connection.server->set_handlers(at_server.handlers());
  {
    Received ignored;
    connection.client->set_handlers(ignored.handlers());
  }
  connection.client->set_handlers(ByteStreamHandlers{});
  connection.client->write("from a dropped stream");
  connection.client.reset();  // pending read and write keep it alive
  ASSERT_TRUE(run_within_wait_limit(connection.io, [&] { return at_server.bytes == "from a dropped stream"; }));
}

TEST(TcpStream, AbortedPeerIsReportedAsReset) {
  asio::io_context io;
  tcp::acceptor acceptor(io, tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0));
  tcp::socket server_socket(io);
  tcp::socket client(io);
  client.connect(acceptor.local_endpoint());
  acceptor.accept(server_socket);
  auto server = make_tcp_stream(std::move(server_socket));
  Received at_server;
  server->set_handlers(at_server.handlers());
  // Linger with a zero timeout makes close() send a RST instead of a FIN.
  client.set_option(asio::socket_base::linger(true, 0));
  client.close();
  ASSERT_TRUE(run_within_wait_limit(io, [&] { return !at_server.closes.empty(); }));
  EXPECT_EQ(at_server.closes, std::vector<std::string>{"connection reset"});
}

// Descriptors this process has open now (the directory listing's own is in every count).
std::size_t open_descriptors() {
  std::size_t count = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator("/proc/self/fd")) ++count;
  return count;
}

// Issue #19 item 3: a close while writes were in flight shut the socket only once they
// finished, so a peer that never reads kept it — ESTABLISHED, MBs queued, one descriptor —
// until it left. Now the bytes get the grace, then the connection is reset.
TEST(TcpStream, ClosingTowardsAPeerThatNeverReadsReleasesTheSocketAfterTheGrace) {
  asio::io_context io;
  tcp::acceptor acceptor(io, tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0));
  tcp::socket never_reads(io);
  never_reads.open(tcp::v4());
  never_reads.set_option(asio::socket_base::receive_buffer_size(4096));
  never_reads.connect(acceptor.local_endpoint());
  tcp::socket server_socket(io);
  acceptor.accept(server_socket);
  const std::size_t descriptors_before = open_descriptors();
  auto server = make_tcp_stream(std::move(server_socket), TcpStreamOptions{std::chrono::milliseconds(300)});
  server->set_handlers(ByteStreamHandlers{});
  // Write as FramedConnection does up to its write-queue limit (1 MiB): the kernel's buffers
  // fill up, the rest waits in the stream's queue.
  const std::string chunk(64 * 1024, 'x');
  ASSERT_TRUE(run_within_wait_limit(io, [&] {
    if (server->queued_bytes() < (std::size_t{1} << 20)) server->write(chunk);
    return server->queued_bytes() >= (std::size_t{1} << 20);
  }));
  testing::run_for(io, std::chrono::milliseconds(50));
  ASSERT_GT(server->queued_bytes(), 0u) << "the peer must not have taken it all";

  const auto closed_at = std::chrono::steady_clock::now();
  server->close();
  ASSERT_TRUE(run_within_wait_limit(io, [&] { return open_descriptors() == descriptors_before - 1; }))
      << "the server's descriptor is still open";
  EXPECT_GE(std::chrono::steady_clock::now() - closed_at, std::chrono::milliseconds(300)) << "the grace was kept";
  // The peer sees the reset (after whatever bytes it still had).
  never_reads.non_blocking(true);
  boost::system::error_code error;
  std::array<char, 65536> buffer{};
  ASSERT_TRUE(run_within_wait_limit(io, [&] {
    never_reads.read_some(asio::buffer(buffer), error);
    return error && error != asio::error::would_block;
  }));
  EXPECT_EQ(error, asio::error::connection_reset) << error.message();
  never_reads.close();
  EXPECT_EQ(open_descriptors(), descriptors_before - 2);
}

TEST(TcpStream, ClosingTowardsAPeerThatReadsDeliversEverythingThenEof) {
  Connection connection;
  Received at_client;
  connection.client->set_handlers(at_client.handlers());
  const std::string big(4 << 20, 'y');   // more than the kernel takes at once
  connection.server->write(big);
  connection.server->close();
  ASSERT_TRUE(run_within_wait_limit(connection.io, [&] { return !at_client.closes.empty(); }));
  EXPECT_EQ(at_client.bytes.size(), big.size());
  EXPECT_EQ(at_client.closes, std::vector<std::string>{"connection closed by peer"});
}

// Issue #19 item 8: the kernel knows the peer has hung up before the close is read (here:
// nobody reads at all) — a server asked to take a new connection can tell.
TEST(TcpStream, APeerThatHungUpIsKnownBeforeItsCloseIsRead) {
  Connection connection;
  EXPECT_FALSE(connection.server->peer_hung_up());
  connection.client->write("unread");
  connection.client->close();
  ASSERT_TRUE(run_within_wait_limit(connection.io, [&] { return connection.server->peer_hung_up(); }));
  EXPECT_TRUE(connection.server->is_open());
  Received at_server;
  connection.server->set_handlers(at_server.handlers());
  ASSERT_TRUE(run_within_wait_limit(connection.io, [&] { return !at_server.closes.empty(); }));
  EXPECT_EQ(at_server.bytes, "unread");
  EXPECT_FALSE(connection.server->peer_hung_up());   // closed now: nothing left to tell
}

TEST(TcpStream, PeerNameIsAddressAndPort) {
  Connection connection;
  const std::string name = connection.server->peer_name();
  EXPECT_EQ(name.rfind("127.0.0.1:", 0), 0u) << name;
  EXPECT_GT(name.size(), std::string("127.0.0.1:").size());
}

}  // namespace
}  // namespace ocp
