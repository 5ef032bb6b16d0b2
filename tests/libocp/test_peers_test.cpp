// The shared test peers (tests/support) themselves: every suite and the conformance suite lean
// on them, so what they report must be exactly what crossed the stream.
#include <gtest/gtest.h>

#include <boost/asio/io_context.hpp>
#include <memory>
#include <string>

#include "framed_peer.hpp"
#include "ocp/pipe.hpp"
#include "ocp/virtual_executor.hpp"
#include "tcp_peers.hpp"

namespace ocp {
namespace {

using testing::FramedPeer;

struct PipePair {
  explicit PipePair(PipeOptions options = {}) {
    PipeEnds ends = make_pipe(executor, options);
    left.attach(ends.a);
    right.attach(ends.b);
  }
  VirtualExecutor executor;
  FramedPeer left{&executor};
  FramedPeer right{&executor};
};

TEST(TestPeers, FramesSentInPiecesArriveWholeWithTheirLengthPrefixAndTime) {
  PipePair pair(PipeOptions{.one_way_delay = Micros{300}, .max_chunk_bytes = 1});
  pair.left.send_in_pieces(R"({"a":1})", 3);
  pair.left.send_payload("second");
  pair.executor.run_until(SimTime{1000});
  ASSERT_EQ(pair.right.frames().size(), 2u);
  EXPECT_EQ(pair.right.frames()[0].payload, R"({"a":1})");
  EXPECT_EQ(pair.right.frames()[0].length_prefix, 7u);
  EXPECT_EQ(pair.right.frames()[0].at, SimTime{300});
  EXPECT_EQ(pair.right.bytes_received(), 2 * frame_header_bytes + 7 + 6);
  EXPECT_EQ(pair.right.poll()->payload, R"({"a":1})");
  EXPECT_EQ(pair.right.poll()->payload, "second");
  EXPECT_FALSE(pair.right.poll().has_value());
}

TEST(TestPeers, AnOversizedFrameIsReportedAndTheNextOneStillArrives) {
  PipePair pair;
  pair.left.send_payload(std::string(max_payload_bytes + 1, 'x'));
  pair.left.send_payload("after");
  pair.executor.run_until(SimTime{1});
  EXPECT_EQ(pair.right.oversized_lengths(), (std::vector<std::uint32_t>{max_payload_bytes + 1}));
  ASSERT_EQ(pair.right.frames().size(), 1u);
  EXPECT_EQ(pair.right.frames()[0].payload, "after");
}

TEST(TestPeers, AStreamCutInsideAFrameIsVisibleAndThePeerCloseIsReportedWithItsTime) {
  PipePair pair;
  pair.executor.call_at(SimTime{50}, [&] {
    pair.left.send_raw(testing::frame_of("truncated").substr(0, 6));
    pair.left.close();
  });
  pair.executor.run_until(SimTime{100});
  EXPECT_TRUE(pair.right.frames().empty());
  EXPECT_TRUE(pair.right.mid_frame());
  EXPECT_TRUE(pair.right.closed_by_peer());
  EXPECT_EQ(pair.right.close_reason(), "closed by peer");
  EXPECT_EQ(pair.right.closed_at(), SimTime{50});
  EXPECT_FALSE(pair.left.closed_by_peer());  // a local close is not the peer's
}

TEST(TestPeers, ADestroyedPeerIgnoresDeliveriesStillInFlight) {
  VirtualExecutor executor;
  PipeEnds ends = make_pipe(executor, PipeOptions{.one_way_delay = Micros{10}});
  FramedPeer sender(&executor);
  sender.attach(ends.a);
  auto receiver = std::make_unique<FramedPeer>(&executor);
  receiver->attach(ends.b);
  sender.send_payload("in flight");
  receiver.reset();
  executor.run_until(SimTime{100});  // must not touch the destroyed receiver
  EXPECT_TRUE(sender.closed_by_peer());
}

TEST(TestPeers, TcpClientAndServerExchangeFramesAndTheServerAcceptsEveryConnection) {
  boost::asio::io_context io;
  testing::TcpTestServer<> server(io);
  server.on_accept = [](FramedPeer& peer) { peer.send_payload("hello client"); };
  ASSERT_TRUE(server.listen().ok());
  ASSERT_NE(server.port(), 0);

  testing::TcpTestClient<> first(io);
  ASSERT_TRUE(first.connect(server.port())) << first.connect_error();
  ASSERT_TRUE(first.wait_for_frames(1));
  EXPECT_EQ(first.frames()[0].payload, "hello client");
  first.send_in_pieces("hello server", 5);
  ASSERT_TRUE(server.wait_for_accepts(1));
  ASSERT_TRUE(first.wait_until([&] { return server.peer(0).frames().size() == 1; }));
  EXPECT_EQ(server.peer(0).frames()[0].payload, "hello server");

  testing::TcpTestClient<> second(io);
  ASSERT_TRUE(second.connect(server.port()));
  ASSERT_TRUE(server.wait_for_accepts(2));
  server.peer(1).close();
  ASSERT_TRUE(second.wait_closed());
  EXPECT_FALSE(second.is_open());
  EXPECT_TRUE(first.is_open());
}

TEST(TestPeers, ConnectingToAClosedPortFailsWithAReason) {
  boost::asio::io_context io;
  std::uint16_t port = 0;
  {
    testing::TcpTestServer<> probe(io);
    ASSERT_TRUE(probe.listen().ok());
    port = probe.port();
  }
  testing::TcpTestClient<> client(io);
  EXPECT_FALSE(client.connect(port));
  EXPECT_FALSE(client.connect_error().empty());
}

}  // namespace
}  // namespace ocp
