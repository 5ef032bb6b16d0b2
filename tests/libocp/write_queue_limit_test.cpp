// A peer that stops reading can never grow our memory: FramedConnection disconnects it with
// PeerError::not_reading once the bytes queued for it would pass write_queue_limit_bytes —
// in virtual time over a pipe (exact), and over real loopback TCP, where the kernel's socket
// buffers fill first and then our own queue.
#include <gtest/gtest.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <chrono>
#include <optional>
#include <string>

#include "ocp/asio/executor.hpp"
#include "ocp/framed_connection.hpp"
#include "ocp/pipe.hpp"
#include "ocp/asio/tcp_stream.hpp"
#include "ocp/virtual_executor.hpp"
#include "tcp_peers.hpp"

namespace ocp {
namespace {

namespace asio = boost::asio;

FramedConnection::Handlers recording(std::optional<CloseReason>& closed) {
  FramedConnection::Handlers handlers;
  handlers.on_payload = [](std::string_view) -> Status { return Ok{}; };
  handlers.on_closed = [&closed](const CloseReason& reason) { closed = reason; };
  return handlers;
}

// The connection under test on `stream`, its close reason recorded in `closed`.
std::shared_ptr<FramedConnection> open_recording(Executor& executor, std::shared_ptr<ByteStream> stream,
                                                 const FramedConnection::Options& options,
                                                 std::optional<CloseReason>& closed) {
  return FramedConnection::open(executor, Logger(executor, "test", make_null_sink()), std::move(stream), options, {},
                                recording(closed));
}

TEST(WriteQueueLimit, APipePeerThatNeverReadsIsDisconnectedAtTheLimitExactly) {
  VirtualExecutor executor;
  PipeEnds ends = make_pipe(executor, PipeOptions{});
  // ends.b never gets handlers: it never reads, so everything sent stays queued for it.
  std::optional<CloseReason> closed;
  FramedConnection::Options options;
  options.write_queue_limit_bytes = 1000;
  auto connection = open_recording(executor, ends.a, options, closed);
  const std::string payload(96, 'x');   // 100 bytes a frame with its header
  for (int frame = 1; frame <= 10; ++frame) {
    ASSERT_TRUE(connection->send(payload)) << "frame " << frame << " fits: " << frame * 100 << " bytes";
    executor.run_for(Micros{1});
    EXPECT_LE(ends.a->queued_bytes(), options.write_queue_limit_bytes);
  }
  const Status eleventh = connection->send(payload);
  ASSERT_FALSE(eleventh);
  EXPECT_EQ(eleventh.error().code, PeerError::not_reading);
  ASSERT_TRUE(closed.has_value());
  EXPECT_EQ(closed->code, PeerError::not_reading);
  EXPECT_EQ(closed->detail, "1000 bytes already queued for it (limit 1000)");
  // The reason is said once (issue #19 item 3: "peer not reading: peer not reading: …").
  EXPECT_EQ(closed->message(), "peer not reading: 1000 bytes already queued for it (limit 1000)");
  EXPECT_EQ(ends.a->queued_bytes(), 1000u) << "nothing was queued past the limit";
  EXPECT_FALSE(connection->is_open());
}

TEST(WriteQueueLimit, APeerThatReadsIsNeverDisconnected) {
  VirtualExecutor executor;
  PipeEnds ends = make_pipe(executor, PipeOptions{});
  std::size_t received = 0;
  ends.b->set_handlers(ByteStreamHandlers{[&](std::string_view bytes) { received += bytes.size(); },
                                          [](const std::string&) {}});
  std::optional<CloseReason> closed;
  FramedConnection::Options options;
  options.write_queue_limit_bytes = 1000;
  auto connection = open_recording(executor, ends.a, options, closed);
  for (int frame = 0; frame < 1000; ++frame) {
    ASSERT_TRUE(connection->send(std::string(96, 'x')));
    executor.run_for(Micros{10});
  }
  EXPECT_FALSE(closed.has_value());
  EXPECT_EQ(received, 100'000u);
}

// Our end of a loopback connection whose other end, `client_socket`, never reads (and has a
// 4 KiB receive buffer); nullptr when the connection did not come up.
std::shared_ptr<ByteStream> accept_deaf_loopback_peer(asio::io_context& io, asio::ip::tcp::socket& client_socket) {
  asio::ip::tcp::acceptor acceptor(io, {asio::ip::make_address("127.0.0.1"), 0});
  asio::ip::tcp::socket server_socket(io);
  bool accepted = false;
  acceptor.async_accept(server_socket, [&](const boost::system::error_code& error) { accepted = !error; });
  client_socket.open(asio::ip::tcp::v4());
  client_socket.set_option(asio::socket_base::receive_buffer_size(4096));
  client_socket.connect(acceptor.local_endpoint());
  if (!testing::run_until(io, [&] { return accepted; })) return nullptr;
  return make_tcp_stream(std::move(server_socket));
}

// A loopback peer that never reads (above), and the connection under test on our end of it.
class WriteQueueLimitLoopback : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(server) << "the loopback connection did not come up"; }
  std::shared_ptr<FramedConnection> open(const FramedConnection::Options& options) {
    return open_recording(executor, server, options, closed);
  }

  asio::io_context io;
  AsioExecutor executor{io};
  asio::ip::tcp::socket client_socket{io};   // connected, never read from
  std::shared_ptr<ByteStream> server = accept_deaf_loopback_peer(io, client_socket);
  std::optional<CloseReason> closed;
};

TEST_F(WriteQueueLimitLoopback, APeerThatNeverReadsIsDisconnectedAndOurQueueStaysBounded) {
  FramedConnection::Options options;
  options.read_timeout = Micros{0};   // this peer is silent on purpose; only the queue may end it
  options.write_queue_limit_bytes = 256 * 1024;
  auto connection = open(options);
  const std::string payload(max_payload_bytes, 'x');
  std::size_t most_queued = 0;
  std::size_t frames_sent = 0;
  // 16 KiB frames as fast as the loop turns: the kernel buffers fill, then our queue does.
  const bool disconnected = testing::run_until(io, [&] {
    if (closed) return true;
    if (connection->send(payload)) ++frames_sent;
    most_queued = std::max(most_queued, server->queued_bytes());
    return closed.has_value();
  }, std::chrono::seconds(30));
  ASSERT_TRUE(disconnected) << "sent " << frames_sent << " frames without a disconnect";
  EXPECT_EQ(closed->code, PeerError::not_reading) << *closed;
  EXPECT_LE(most_queued, options.write_queue_limit_bytes) << "our memory stayed bounded";
  EXPECT_GT(frames_sent, 16u) << "the queue filled up before the disconnect";
}

// The 10 s rule of both TCP APIs, over real loopback TCP (with a 300 ms stall for the test):
// a peer that never reads is dropped because it took nothing for the stall time — once the
// kernel's buffers are full our queue holds bytes, and no byte of it is taken again — long
// before a generous byte cap. Virtual time, exactly, on both ports: tests/world/not_reading_test.cpp.
TEST_F(WriteQueueLimitLoopback, APeerThatTakesNothingForTheStallTimeIsDisconnected) {
  FramedConnection::Options options;
  options.read_timeout = Micros{0};
  options.write_stall_timeout = Micros{300'000};
  options.write_queue_limit_bytes = 512 * 1024 * 1024;   // never the reason here
  auto connection = open(options);
  const std::string payload(4096, 'x');
  std::optional<std::chrono::steady_clock::time_point> queue_first_held;
  const bool disconnected = testing::run_until(io, [&] {
    if (closed) return true;
    (void)connection->send(payload);
    if (!queue_first_held && server->queued_bytes() > 0) queue_first_held = std::chrono::steady_clock::now();
    return closed.has_value();
  }, std::chrono::seconds(60));
  ASSERT_TRUE(disconnected) << "never disconnected";
  EXPECT_EQ(closed->code, PeerError::not_reading) << *closed;
  EXPECT_NE(closed->detail.find("took none of the"), std::string::npos) << *closed;
  ASSERT_TRUE(queue_first_held.has_value());
  EXPECT_GE(std::chrono::steady_clock::now() - *queue_first_held, std::chrono::milliseconds(300))
      << "not before the stall time";
}

}  // namespace
}  // namespace ocp
