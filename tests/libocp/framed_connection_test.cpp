// FramedConnection: the SPEC §2 connection rules shared by the vehicle (:4000) and operator
// client (:4001) APIs, in virtual time over an in-memory pipe.
#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "ocp/framed_connection.hpp"
#include "ocp/pipe.hpp"
#include "ocp/virtual_executor.hpp"

namespace ocp {
namespace {

using namespace std::chrono_literals;

std::string frame_header(std::uint32_t length) {
  std::string header(frame_header_bytes, '\0');
  for (std::size_t index = 0; index < frame_header_bytes; ++index) {
    header[index] = static_cast<char>((length >> (8 * index)) & 0xffU);
  }
  return header;
}

std::string framed(std::string_view payload) {
  return frame_header(static_cast<std::uint32_t>(payload.size())) + std::string(payload);
}

Error bad_payload(std::string detail) {
  return Error{make_error_code(PeerError::malformed_json), std::move(detail)};
}

// One connection on end b of a pipe; the test plays the peer on end a.
struct Fixture {
  VirtualExecutor executor;
  PipeEnds ends = make_pipe(executor, PipeOptions{.name_a = "pipe:peer"});
  std::vector<std::string> log_lines;
  std::vector<std::string> payloads;
  std::vector<CloseReason> close_reasons;
  std::vector<SimTime> closed_at;
  std::uint64_t bytes_in = 0;
  std::uint64_t bytes_out = 0;
  std::uint64_t oversized = 0;
  std::string peer_received;
  bool peer_closed = false;
  std::shared_ptr<FramedConnection> connection;

  explicit Fixture(Micros read_timeout = 2000ms) {
    ends.a->set_handlers(ByteStreamHandlers{
        [this](std::string_view bytes) { peer_received += bytes; },
        [this](const std::string&) { peer_closed = true; }});
    Logger logger(executor, "test", [this](const LogRecord& record) {
      log_lines.emplace_back(std::string(log_level_name(record.level)) + " " + std::string(record.message));
    });
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

  bool logged(std::string_view needle) const {
    for (const std::string& line : log_lines) {
      if (line.find(needle) != std::string::npos) return true;
    }
    return false;
  }
};

TEST(FramedConnection, DeliversEachPayloadAndCountsBytes) {
  Fixture fixture;
  fixture.ends.a->write(framed("one") + framed("two"));
  fixture.executor.run_until(1ms);
  EXPECT_EQ(fixture.payloads, (std::vector<std::string>{"one", "two"}));
  EXPECT_EQ(fixture.bytes_in, 2 * frame_header_bytes + 6);
  EXPECT_TRUE(fixture.close_reasons.empty());
}

TEST(FramedConnection, ClosesAfterExactlyTheReadTimeoutWithoutAByte) {
  Fixture fixture;
  fixture.executor.call_at(SimTime{500'000}, [&] { fixture.ends.a->write(framed("x")); });
  fixture.executor.run_until(SimTime{2'499'999});
  EXPECT_TRUE(fixture.close_reasons.empty());
  fixture.executor.run_until(SimTime{2'500'000});
  ASSERT_EQ(fixture.close_reasons.size(), 1u);
  EXPECT_EQ(fixture.closed_at[0], SimTime{2'500'000});
  EXPECT_EQ(fixture.close_reasons[0],
            (CloseReason{PeerError::read_timeout, "no data from the widget for 2000 ms"}));
  EXPECT_TRUE(fixture.logged("WARN closing widget connection pipe:peer: read timeout"));
  fixture.executor.run_until(SimTime{2'500'001});
  EXPECT_TRUE(fixture.peer_closed);
}

TEST(FramedConnection, ReadTimeoutAlsoRunsInsideAFrame) {
  Fixture fixture;
  fixture.executor.call_at(SimTime{1'000'000}, [&] { fixture.ends.a->write(frame_header(10) + "abc"); });
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
  fixture.ends.a->write(framed(std::string(max_payload_bytes + 1, 'x')) + framed("after"));
  fixture.executor.run_until(1ms);
  EXPECT_EQ(fixture.oversized, 1u);
  EXPECT_TRUE(fixture.logged("WARN widget pipe:peer: dropped oversized frame of 16385 bytes (limit 16384)"));
  EXPECT_EQ(fixture.payloads, (std::vector<std::string>{"after"}));
  EXPECT_TRUE(fixture.close_reasons.empty());
}

TEST(FramedConnection, PayloadErrorClosesWithItsReason) {
  Fixture fixture;
  fixture.executor.call_at(SimTime{7000}, [&] { fixture.ends.a->write(framed("bad") + framed("never")); });
  fixture.executor.run_until(20ms);
  const CloseReason reason = bad_payload("not json");
  EXPECT_EQ(fixture.close_reasons, (std::vector<CloseReason>{reason}));
  EXPECT_EQ(fixture.closed_at[0], SimTime{7000});
  EXPECT_TRUE(fixture.payloads.empty());  // nothing after the bad frame is dispatched
  EXPECT_TRUE(fixture.logged("WARN closing widget connection pipe:peer: " + reason.message()));
  EXPECT_TRUE(fixture.peer_closed);
}

TEST(FramedConnection, EndOfStreamInsideAFrameClosesWithTheTruncationReason) {
  Fixture fixture;
  const std::string partial = frame_header(10) + "abc";
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
  EXPECT_TRUE(fixture.logged("stream ended inside a frame"));
}

TEST(FramedConnection, PeerCloseBetweenFramesIsReportedAsPeerClosed) {
  Fixture fixture;
  fixture.ends.a->write(framed("last"));
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
  EXPECT_EQ(fixture.peer_received, framed("hello"));  // the oversized one never left
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
  EXPECT_TRUE(fixture.peer_received.empty());
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
  a->write(framed("one") + framed("two"));
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
  EXPECT_TRUE(fixture.peer_closed);
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
