#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "ocp/pipe.hpp"
#include "ocp/virtual_executor.hpp"

namespace ocp {
namespace {

using namespace std::chrono_literals;

// Records what one end receives, with the virtual time of each callback.
struct Recorder {
  std::vector<std::pair<std::string, SimTime>> chunks;
  std::vector<std::pair<std::string, SimTime>> closes;
  std::string all() const {
    std::string joined;
    for (const auto& chunk : chunks) {
      joined += chunk.first;
    }
    return joined;
  }
  ByteStreamHandlers handlers(const Executor& executor) {
    return ByteStreamHandlers{
        [this, &executor](std::string_view bytes) { chunks.emplace_back(std::string(bytes), executor.now()); },
        [this, &executor](const std::string& reason) { closes.emplace_back(reason, executor.now()); }};
  }
};

TEST(Pipe, BytesArriveAtThePeerAfterTheOneWayDelayInOrder) {
  VirtualExecutor executor;
  auto [a, b] = make_pipe(executor, PipeOptions{.one_way_delay = 5ms});
  Recorder at_a;
  Recorder at_b;
  a->set_handlers(at_a.handlers(executor));
  b->set_handlers(at_b.handlers(executor));
  a->write("hello ");
  executor.run_until(SimTime{1000});
  a->write("world");
  b->write("back");
  executor.run_until(SimTime{4999});
  EXPECT_TRUE(at_b.chunks.empty());
  executor.run_until(SimTime{10'000});
  ASSERT_EQ(at_b.chunks.size(), 2u);
  EXPECT_EQ(at_b.chunks[0], std::make_pair(std::string("hello "), SimTime{5000}));
  EXPECT_EQ(at_b.chunks[1], std::make_pair(std::string("world"), SimTime{6000}));
  ASSERT_EQ(at_a.chunks.size(), 1u);
  EXPECT_EQ(at_a.chunks[0], std::make_pair(std::string("back"), SimTime{6000}));
}

// A delayed pipe that never runs empty (a write every millisecond, 40 ms in flight): every
// write still arrives whole, in order, 40 ms after it was made, and what is queued towards the
// peer is exactly what is in flight.
TEST(Pipe, DelayedPipeThatNeverRunsEmptyDeliversEveryWriteInOrder) {
  VirtualExecutor executor;
  auto [a, b] = make_pipe(executor, PipeOptions{.one_way_delay = 40ms});
  Recorder at_b;
  b->set_handlers(at_b.handlers(executor));
  std::vector<std::string> written;
  for (int i = 0; i < 3000; ++i) {
    executor.run_until(SimTime{i * 1000});
    written.push_back(std::to_string(i) + std::string(static_cast<std::size_t>(i % 300), 'x'));
    a->write(written.back());
    if (i >= 40) {
      std::size_t in_flight = 0;
      for (int j = i - 39; j <= i; ++j) in_flight += written[static_cast<std::size_t>(j)].size();
      ASSERT_EQ(a->queued_bytes(), in_flight) << "at write " << i;
    }
  }
  executor.run_until(SimTime{3'100'000});
  ASSERT_EQ(at_b.chunks.size(), written.size());
  for (std::size_t i = 0; i < written.size(); ++i) {
    ASSERT_EQ(at_b.chunks[i].first, written[i]) << "write " << i;
    ASSERT_EQ(at_b.chunks[i].second, SimTime{static_cast<std::int64_t>(i) * 1000 + 40'000}) << "write " << i;
  }
  EXPECT_EQ(a->queued_bytes(), 0u);
}

TEST(Pipe, ZeroDelayStillDeliversThroughTheExecutor) {
  VirtualExecutor executor;
  auto [a, b] = make_pipe(executor);
  Recorder at_b;
  b->set_handlers(at_b.handlers(executor));
  a->write("x");
  EXPECT_TRUE(at_b.chunks.empty());
  executor.run_until(SimTime{0});
  EXPECT_EQ(at_b.all(), "x");
}

TEST(Pipe, MaxChunkBytesSplitsDeliveries) {
  VirtualExecutor executor;
  auto [a, b] = make_pipe(executor, PipeOptions{.max_chunk_bytes = 3});
  Recorder at_b;
  b->set_handlers(at_b.handlers(executor));
  a->write("abcdefgh");
  executor.run_for(1ms);
  ASSERT_EQ(at_b.chunks.size(), 3u);
  EXPECT_EQ(at_b.chunks[0].first, "abc");
  EXPECT_EQ(at_b.chunks[1].first, "def");
  EXPECT_EQ(at_b.chunks[2].first, "gh");
}

TEST(Pipe, CloseDeliversPendingBytesThenReportsOnceToThePeer) {
  VirtualExecutor executor;
  auto [a, b] = make_pipe(executor, PipeOptions{.one_way_delay = 2ms});
  Recorder at_a;
  Recorder at_b;
  a->set_handlers(at_a.handlers(executor));
  b->set_handlers(at_b.handlers(executor));
  a->write("last words");
  a->close();
  a->close();
  EXPECT_FALSE(a->is_open());
  a->write("ignored");
  executor.run_for(10ms);
  EXPECT_EQ(at_b.all(), "last words");
  ASSERT_EQ(at_b.closes.size(), 1u);
  EXPECT_EQ(at_b.closes[0], std::make_pair(std::string("closed by peer"), SimTime{2000}));
  EXPECT_FALSE(b->is_open());
  EXPECT_TRUE(at_a.closes.empty());  // a local close is not reported locally
  b->write("to nobody");
  b->close();
  executor.run_for(10ms);
  EXPECT_TRUE(at_a.chunks.empty());
  EXPECT_TRUE(at_a.closes.empty());
}

TEST(Pipe, BytesArrivingBeforeHandlersAreBufferedUntilReadingStarts) {
  VirtualExecutor executor;
  auto [a, b] = make_pipe(executor, PipeOptions{.one_way_delay = 1ms});
  a->write("early ");
  a->write("bird");
  executor.run_for(5ms);
  Recorder at_b;
  b->set_handlers(at_b.handlers(executor));
  EXPECT_TRUE(at_b.chunks.empty());  // handed over from the executor, not inside set_handlers
  a->write(" late");
  executor.run_for(5ms);
  EXPECT_EQ(at_b.all(), "early bird late");
  EXPECT_EQ(at_b.chunks.front().second, SimTime{5000});
}

TEST(Pipe, CloseBeforeHandlersIsReportedAfterBufferedBytes) {
  VirtualExecutor executor;
  auto [a, b] = make_pipe(executor);
  a->write("bye");
  a->close();
  executor.run_for(1ms);
  std::vector<std::string> events;
  b->set_handlers(ByteStreamHandlers{[&](std::string_view bytes) { events.emplace_back(bytes); },
                                     [&](const std::string& reason) { events.push_back("closed: " + reason); }});
  executor.run_for(1ms);
  EXPECT_EQ(events, (std::vector<std::string>{"bye", "closed: closed by peer"}));
}

TEST(Pipe, LocalCloseDropsBytesStillInFlightTowardsIt) {
  VirtualExecutor executor;
  auto [a, b] = make_pipe(executor, PipeOptions{.one_way_delay = 1ms});
  Recorder at_a;
  a->set_handlers(at_a.handlers(executor));
  b->write("in flight");
  a->close();
  executor.run_for(5ms);
  EXPECT_TRUE(at_a.chunks.empty());
  EXPECT_TRUE(at_a.closes.empty());
}

TEST(Pipe, DestroyingAnEndWithPendingDeliveriesIsSafeAndTellsThePeer) {
  VirtualExecutor executor;
  auto ends = make_pipe(executor, PipeOptions{.one_way_delay = 1ms});
  Recorder at_a;
  ends.a->set_handlers(at_a.handlers(executor));
  Recorder at_b;
  ends.b->set_handlers(at_b.handlers(executor));
  ends.a->write("towards b");
  ends.b->write("towards a");
  ends.b.reset();
  executor.run_for(5ms);
  EXPECT_EQ(at_a.all(), "towards a");
  ASSERT_EQ(at_a.closes.size(), 1u);
  EXPECT_TRUE(at_b.chunks.empty());
}

TEST(Pipe, HandlerMayReplaceHandlersWhileRunning) {
  VirtualExecutor executor;
  auto [a, b] = make_pipe(executor, PipeOptions{.max_chunk_bytes = 1});
  std::string first;
  std::string second;
  auto receiver = b;
  b->set_handlers(ByteStreamHandlers{[&, receiver](std::string_view bytes) {
                                       first += bytes;
                                       receiver->set_handlers(ByteStreamHandlers{
                                           [&](std::string_view more) { second += more; }, nullptr});
                                     },
                                     nullptr});
  a->write("xyz");
  executor.run_for(1ms);
  EXPECT_EQ(first, "x");
  EXPECT_EQ(second, "yz");
}

TEST(Pipe, PeerNamesComeFromTheOptions) {
  VirtualExecutor executor;
  auto [a, b] = make_pipe(executor, PipeOptions{.name_a = "pipe:operator", .name_b = "pipe:truck-1"});
  EXPECT_EQ(a->peer_name(), "pipe:truck-1");
  EXPECT_EQ(b->peer_name(), "pipe:operator");
  EXPECT_TRUE(a->is_open());
}

}  // namespace
}  // namespace ocp
