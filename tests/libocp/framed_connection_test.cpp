// FramedConnection: the SPEC §2 connection rules shared by the vehicle (:4000) and operator
// client (:4001) APIs, in virtual time over an in-memory pipe.
#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "ocp/framed_connection.hpp"
#include "ocp/pipe.hpp"
#include "captured_log.hpp"
#include "framed_peer.hpp"
#include "ocp/virtual_executor.hpp"

namespace ocp {
namespace {

using namespace std::chrono_literals;

using testing::frame_of;

// The first `kept` bytes of a frame of `length` payload bytes: a stream that ends inside it.
std::string partial_frame(std::size_t length, std::size_t kept) {
  return frame_of(std::string(length, 'p')).substr(0, kept);
}

Error bad_payload(std::string detail) {
  return Error{make_error_code(PeerError::malformed_json), std::move(detail)};
}

// One connection on end b of a pipe; the test plays the peer on end a.
struct Fixture {
  VirtualExecutor executor;
  PipeEnds ends = make_pipe(executor, PipeOptions{.name_a = "pipe:peer"});
  testing::CapturedLog log;
  std::vector<std::string> payloads;
  std::vector<CloseReason> close_reasons;
  std::vector<SimTime> closed_at;
  std::uint64_t bytes_in = 0;
  std::uint64_t bytes_out = 0;
  std::uint64_t oversized = 0;
  testing::FramedPeer peer{&executor};  // the far end: writes go straight to ends.a
  std::shared_ptr<FramedConnection> connection;

  explicit Fixture(Micros read_timeout = 2000ms) {
    peer.attach(ends.a);
    Logger logger(executor, "test", log.sink());
    FramedConnection::Handlers handlers;
    handlers.on_payload = [this](std::string_view payload) -> Status {
      if (payload == "bad") return bad_payload("not json");
      payloads.emplace_back(payload);
      return Ok{};
    };
    handlers.on_closed = [this](const CloseReason& reason) {
      close_reasons.push_back(reason);
      closed_at.push_back(executor.now());
      connection.reset();  // owners drop the connection from inside its callback
    };
    connection = FramedConnection::open(
        executor, logger, ends.b,
        FramedConnection::Options{.label = "widget", .read_timeout = read_timeout},
        FramedConnection::Counters{.bytes_in = &bytes_in, .bytes_out = &bytes_out,
                                   .oversized_frames_dropped = &oversized},
        std::move(handlers));
  }
};

TEST(FramedConnection, ServerOptionsFollowFromTheWire) {
  EventBus events;
  const Component component{};
  const auto vehicle = FramedConnection::server_options(Wire::vehicle, 2000ms, events, component);
  EXPECT_EQ(vehicle.label, "vehicle");
  EXPECT_EQ(vehicle.read_timeout, 2000ms);
  EXPECT_EQ(vehicle.events, &events);
  EXPECT_EQ(vehicle.wire, Wire::vehicle);
  EXPECT_EQ(vehicle.inbound_kind, WireMessageKind::vehicle_response);
  EXPECT_EQ(vehicle.outbound_kind, WireMessageKind::control);
  EXPECT_EQ(vehicle.write_queue_limit_bytes, default_write_queue_limit_bytes);
  const auto client = FramedConnection::server_options(Wire::operator_, 500ms, events, component);
  EXPECT_EQ(client.label, "tcp client");
  EXPECT_EQ(client.read_timeout, 500ms);
  EXPECT_EQ(client.wire, Wire::operator_);
  EXPECT_EQ(client.inbound_kind, WireMessageKind::client_ocp_shared);
  EXPECT_EQ(client.outbound_kind, WireMessageKind::vehicle_ocp_shared);
}

TEST(FramedConnection, DeliversEachPayloadAndCountsBytes) {
  Fixture fixture;
  fixture.ends.a->write(frame_of("one") + frame_of("two"));
  fixture.executor.run_until(1ms);
  EXPECT_EQ(fixture.payloads, (std::vector<std::string>{"one", "two"}));
  EXPECT_EQ(fixture.bytes_in, 2 * frame_header_bytes + 6);
  EXPECT_TRUE(fixture.close_reasons.empty());
}

TEST(FramedConnection, ClosesAfterExactlyTheReadTimeoutWithoutAByte) {
  Fixture fixture;
  fixture.executor.call_at(SimTime{500'000}, [&] { fixture.ends.a->write(frame_of("x")); });
  fixture.executor.run_until(SimTime{2'499'999});
  EXPECT_TRUE(fixture.close_reasons.empty());
  fixture.executor.run_until(SimTime{2'500'000});
  ASSERT_EQ(fixture.close_reasons.size(), 1u);
  EXPECT_EQ(fixture.closed_at[0], SimTime{2'500'000});
  EXPECT_EQ(fixture.close_reasons[0],
            (CloseReason{PeerError::read_timeout, "no data from the widget for 2000 ms"}));
  EXPECT_TRUE(fixture.log.contains(LogLevel::warn, "closing widget connection pipe:peer: read timeout"));
  fixture.executor.run_until(SimTime{2'500'001});
  EXPECT_TRUE(fixture.peer.closed_by_peer());
}

TEST(FramedConnection, ReadTimeoutAlsoRunsInsideAFrame) {
  Fixture fixture;
  fixture.executor.call_at(SimTime{1'000'000}, [&] { fixture.ends.a->write(partial_frame(10, frame_header_bytes + 3)); });
  fixture.executor.run_until(SimTime{2'999'999});
  EXPECT_TRUE(fixture.close_reasons.empty());
  fixture.executor.run_until(SimTime{3'000'000});
  ASSERT_EQ(fixture.closed_at.size(), 1u);
  EXPECT_EQ(fixture.closed_at[0], SimTime{3'000'000});
}

TEST(FramedConnection, ZeroReadTimeoutNeverCloses) {
  Fixture fixture(Micros{0});
  fixture.executor.run_until(SimTime{60'000'000});
  EXPECT_TRUE(fixture.close_reasons.empty());
  ASSERT_NE(fixture.connection, nullptr);
  EXPECT_TRUE(fixture.connection->is_open());
}

TEST(FramedConnection, OversizedInboundFrameIsDrainedCountedAndTheConnectionKept) {
  Fixture fixture;
  fixture.ends.a->write(frame_of(std::string(max_payload_bytes + 1, 'x')) + frame_of("after"));
  fixture.executor.run_until(1ms);
  EXPECT_EQ(fixture.oversized, 1u);
  EXPECT_TRUE(fixture.log.contains(LogLevel::warn, "widget pipe:peer: dropped oversized frame of 16385 bytes (limit 16384)"));
  EXPECT_EQ(fixture.payloads, (std::vector<std::string>{"after"}));
  EXPECT_TRUE(fixture.close_reasons.empty());
}

// A peer sending nothing but oversized frames (as fast as loopback goes: tens of thousands a
// second) logs one line, then a count every 5 s, then one at the close — not a line a frame.
TEST(FramedConnection, AFloodOfOversizedFramesIsLoggedOnceThenCounted) {
  Fixture fixture(Micros{0});
  const std::string oversized = frame_of(std::string(max_payload_bytes + 1, 'x'));
  for (int k = 0; k < 10'000; ++k) {   // one a millisecond for 10 s
    fixture.ends.a->write(oversized);
    fixture.executor.run_until(SimTime{(k + 1) * 1000});
  }
  for (int k = 0; k < 3; ++k) fixture.ends.a->write(oversized);   // and a last few
  fixture.executor.run_until(SimTime{10'002'000});
  EXPECT_EQ(fixture.oversized, 10'003u);
  ASSERT_NE(fixture.connection, nullptr);
  fixture.connection->close(CloseReason{LocalError::shut_down, "test over"});
  std::vector<std::string> lines;
  for (const auto& line : fixture.log.lines()) {
    if (line.message.find("oversized") != std::string::npos) lines.push_back(line.message);
  }
  ASSERT_EQ(lines.size(), 4u) << ::testing::PrintToString(lines);
  EXPECT_EQ(lines[0], "widget pipe:peer: dropped oversized frame of 16385 bytes (limit 16384); connection kept");
  EXPECT_EQ(lines[1], "widget pipe:peer: dropped 4999 more oversized frames in the last 5 s");
  EXPECT_EQ(lines[2], "widget pipe:peer: dropped 5000 more oversized frames in the last 5 s");
  EXPECT_EQ(lines[3].rfind("widget pipe:peer: dropped 3 more oversized frames in the last ", 0), 0u) << lines[3];
}

TEST(FramedConnection, PayloadErrorClosesWithItsReason) {
  Fixture fixture;
  fixture.executor.call_at(SimTime{7000}, [&] { fixture.ends.a->write(frame_of("bad") + frame_of("never")); });
  fixture.executor.run_until(20ms);
  const CloseReason reason = bad_payload("not json");
  EXPECT_EQ(fixture.close_reasons, (std::vector<CloseReason>{reason}));
  EXPECT_EQ(fixture.closed_at[0], SimTime{7000});
  EXPECT_TRUE(fixture.payloads.empty());  // nothing after the bad frame is dispatched
  EXPECT_TRUE(fixture.log.contains(LogLevel::warn, "closing widget connection pipe:peer: " + reason.message()));
  EXPECT_TRUE(fixture.peer.closed_by_peer());
}

// Our own stop is a normal end: the close is logged, but not as a warning.
TEST(FramedConnection, OurOwnShutdownIsLoggedAsInfoNotWarning) {
  Fixture fixture;
  const CloseReason reason{LocalError::shut_down, "streamer stopped"};
  fixture.connection->close(reason);
  EXPECT_EQ(fixture.close_reasons, (std::vector<CloseReason>{reason}));
  EXPECT_TRUE(fixture.log.contains(LogLevel::info, "closing widget connection pipe:peer: " + reason.message()));
  EXPECT_FALSE(fixture.log.contains(LogLevel::warn, "closing widget connection"));
}

TEST(FramedConnection, EndOfStreamInsideAFrameClosesWithTheTruncationReason) {
  Fixture fixture;
  const std::string partial = partial_frame(10, frame_header_bytes + 3);
  FrameDecoder reference;
  FrameEvent event;
  reference.put(partial, event);
  const Status expected = reference.finish();
  ASSERT_FALSE(expected.ok());

  fixture.ends.a->write(partial);
  fixture.ends.a->close();
  fixture.executor.run_until(1ms);
  EXPECT_EQ(fixture.close_reasons, (std::vector<CloseReason>{expected.error()}));
  EXPECT_EQ(fixture.close_reasons[0].code, PeerError::truncated_frame);
  EXPECT_TRUE(fixture.log.contains("stream ended inside a frame"));
}

TEST(FramedConnection, PeerCloseBetweenFramesIsReportedAsPeerClosed) {
  Fixture fixture;
  fixture.ends.a->write(frame_of("last"));
  fixture.ends.a->close();
  fixture.executor.run_until(1ms);
  EXPECT_EQ(fixture.payloads, (std::vector<std::string>{"last"}));
  ASSERT_EQ(fixture.close_reasons.size(), 1u);
  EXPECT_EQ(fixture.close_reasons[0].code, PeerError::closed_by_peer) << fixture.close_reasons[0].message();
}

TEST(FramedConnection, SendFramesThePayloadAndRefusesAnOversizedOne) {
  Fixture fixture;
  ASSERT_TRUE(fixture.connection->send("hello").ok());
  const Status refused = fixture.connection->send(std::string(max_payload_bytes + 1, 'x'));
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().code, LocalError::frame_too_large);
  fixture.executor.run_until(1ms);
  ASSERT_EQ(fixture.peer.frames().size(), 1u);  // the oversized one never left
  EXPECT_EQ(fixture.peer.frames()[0].payload, "hello");
  EXPECT_EQ(fixture.peer.bytes_received(), frame_header_bytes + 5);
  EXPECT_EQ(fixture.bytes_out, frame_header_bytes + 5);
  EXPECT_TRUE(fixture.connection->is_open());
}

TEST(FramedConnection, SendAfterCloseFails) {
  Fixture fixture;
  auto keep = fixture.connection;
  keep->close(CloseReason{LocalError::shut_down, "done"});
  const Status sent = keep->send("late");
  EXPECT_FALSE(sent.ok());
  fixture.executor.run_until(1ms);
  EXPECT_EQ(fixture.peer.bytes_received(), 0u);
}

TEST(FramedConnection, OnClosedIsReportedExactlyOnceWhateverClosesIt) {
  Fixture fixture;
  auto keep = fixture.connection;  // survive the fixture's reset inside on_closed
  keep->close(CloseReason{LocalError::shut_down, "local"});
  keep->close(CloseReason{LocalError::shut_down, "again"});
  fixture.ends.a->close();
  fixture.executor.run_until(10'000ms);  // a read timeout would fire here if still armed
  EXPECT_EQ(fixture.close_reasons, (std::vector<CloseReason>{{LocalError::shut_down, "local"}}));
  EXPECT_FALSE(keep->is_open());
}

TEST(FramedConnection, OwnerMayDropItFromInsideOnPayload) {
  Fixture fixture;
  std::weak_ptr<FramedConnection> weak = fixture.connection;
  // Re-open with a payload handler that drops the last reference mid-chunk.
  fixture.connection.reset();
  EXPECT_TRUE(weak.expired());
  auto [a, b] = make_pipe(fixture.executor);
  std::shared_ptr<FramedConnection> owner;
  int payloads = 0;
  FramedConnection::Handlers handlers;
  handlers.on_payload = [&](std::string_view) -> Status {
    ++payloads;
    owner.reset();
    return Ok{};
  };
  owner = FramedConnection::open(fixture.executor, Logger(fixture.executor, "test", make_null_sink()), b,
                                 FramedConnection::Options{}, FramedConnection::Counters{},
                                 std::move(handlers));
  weak = owner;
  a->write(frame_of("one") + frame_of("two"));
  fixture.executor.run_until(1ms);
  EXPECT_GE(payloads, 1);
  EXPECT_TRUE(weak.expired());
  fixture.executor.run_until(10'000ms);  // the dead connection's timer and handlers are inert
  EXPECT_FALSE(a->is_open() && b->is_open());
}

TEST(FramedConnection, DestroyingItClosesTheStreamWithoutReporting) {
  Fixture fixture;
  fixture.executor.run_until(1ms);
  fixture.connection.reset();
  fixture.executor.run_until(5000ms);
  EXPECT_TRUE(fixture.close_reasons.empty());
  EXPECT_TRUE(fixture.peer.closed_by_peer());
}

TEST(FramedConnection, AnAlreadyClosedStreamIsReportedFromTheExecutor) {
  VirtualExecutor executor;
  auto [a, b] = make_pipe(executor);
  b->close();
  std::vector<CloseReason> reasons;
  FramedConnection::Handlers handlers;
  handlers.on_closed = [&](const CloseReason& reason) { reasons.push_back(reason); };
  auto connection = FramedConnection::open(executor, Logger(executor, "test", make_null_sink()), b,
                                           FramedConnection::Options{}, FramedConnection::Counters{},
                                           std::move(handlers));
  EXPECT_TRUE(reasons.empty());  // never from inside open()
  executor.run_until(SimTime{0});
  ASSERT_EQ(reasons.size(), 1u);
  EXPECT_EQ(reasons[0].code, LocalError::stream_closed);
  EXPECT_FALSE(connection->is_open());
}

}  // namespace
}  // namespace ocp
