// Trace-driven link directions (Impairments::trace): a drop-tail queue in front of a Mahimahi
// delivery trace, in virtual time, exactly.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "ocp/com_channel.hpp"
#include "ocp/delivery_trace.hpp"
#include "ocp/virtual_executor.hpp"

namespace ocp {
namespace {

using namespace std::chrono_literals;

std::shared_ptr<const DeliveryTrace> trace_of(const std::string& text) {
  auto trace = DeliveryTrace::parse(text, "test.trace");
  EXPECT_TRUE(trace.ok());
  return std::make_shared<const DeliveryTrace>(std::move(trace).value());
}

// Lines first, first+step, …, up to last.
std::string every(int step_ms, int first, int last) {
  std::string text;
  for (int ms = first; ms <= last; ms += step_ms) text += std::to_string(ms) + "\n";
  return text;
}

VideoFrame frame_of_wire_size(std::uint64_t number, std::size_t wire_bytes) {
  VideoFrame frame{"front", number, std::nullopt, 0};
  frame.size_bytes = static_cast<std::uint32_t>(wire_bytes - wire_size_bytes(frame));
  return frame;
}

struct Arrivals {
  std::vector<std::pair<std::uint64_t, SimTime>> list;
  void attach(LinkDirection& direction, const Executor& executor) {
    direction.set_receiver([this, &executor](LinkMessage&& message) {
      list.emplace_back(std::get<VideoFrame>(message).frame_number, executor.now());
    });
  }
};

TEST(TraceLink, ConstantRateTraceDeliversItsRateWithinOnePercent) {
  // One 1500-byte opportunity per millisecond: 12 Mbit/s. Offered: 10-packet frames every
  // 5 ms (24 Mbit/s), so the queue never runs dry and the trace alone sets the throughput.
  VirtualExecutor executor;
  LinkDirection link(executor, 1);
  link.set_impairments(Impairments{.trace = trace_of(every(1, 1, 1000)), .queue_limit_packets = 200});
  Arrivals arrivals;
  arrivals.attach(link, executor);
  for (int i = 0; i < 4000; ++i) {
    executor.call_at(SimTime{i * 5000}, [&, i] { link.send(frame_of_wire_size(static_cast<std::uint64_t>(i), 15'000)); });
  }
  executor.run_until(SimTime{10'000'000});
  const double bits_per_second = static_cast<double>(arrivals.list.size()) * 15'000 * 8 / 10.0;
  EXPECT_NEAR(bits_per_second, 12e6, 12e6 * 0.01);
  EXPECT_GT(link.counters().dropped, 0u);
}

TEST(TraceLink, AMessageOfKPacketsWaitsForKOpportunities) {
  VirtualExecutor executor;
  LinkDirection link(executor, 1);
  link.set_impairments(Impairments{.delay = 5ms, .trace = trace_of(every(10, 10, 100))});
  Arrivals arrivals;
  arrivals.attach(link, executor);
  link.send(frame_of_wire_size(1, 3 * 1500 - 100));   // 3 packets: opportunities at 10, 20, 30 ms
  link.send(frame_of_wire_size(2, 1500));              // 1 packet: the next one, 40 ms
  executor.run_until(SimTime{12'000});
  EXPECT_EQ(link.counters().queue_depth_bytes, 3 * 1500 - 100 - 1500 + 1500);  // 2 of 3 packets + frame 2
  link.send(frame_of_wire_size(3, 1501));              // 2 packets: 50, 60 ms
  executor.run_for(1s);
  EXPECT_EQ(arrivals.list, (std::vector<std::pair<std::uint64_t, SimTime>>{
                               {1, SimTime{35'000}}, {2, SimTime{45'000}}, {3, SimTime{65'000}}}));
}

TEST(TraceLink, AnIdleLinkWastesItsOpportunities) {
  VirtualExecutor executor;
  LinkDirection link(executor, 1);
  link.set_impairments(Impairments{.trace = trace_of(every(10, 10, 1000))});
  Arrivals arrivals;
  arrivals.attach(link, executor);
  executor.run_until(SimTime{95'000});
  link.send(frame_of_wire_size(1, 3000));  // 100 and 110 ms, not the unused 10…90 ms
  executor.run_for(1s);
  ASSERT_EQ(arrivals.list.size(), 1u);
  EXPECT_EQ(arrivals.list[0].second, SimTime{110'000});
}

TEST(TraceLink, OpportunitiesExactlyAtNowAreUsable) {
  VirtualExecutor executor;
  LinkDirection link(executor, 1);
  link.set_impairments(Impairments{.trace = trace_of("10\n10\n10\n20\n")});
  Arrivals arrivals;
  arrivals.attach(link, executor);
  executor.run_until(SimTime{10'000});
  link.send(frame_of_wire_size(1, 4500));   // three packets, all three at 10 ms
  link.send(frame_of_wire_size(2, 100));    // the next: 20 ms
  executor.run_for(1s);
  EXPECT_EQ(arrivals.list, (std::vector<std::pair<std::uint64_t, SimTime>>{{1, SimTime{10'000}}, {2, SimTime{20'000}}}));
}

TEST(TraceLink, QueueOverflowDropsWholeMessagesAndPublishesIt) {
  VirtualExecutor executor;
  LinkDirection link(executor, 1);
  link.set_impairments(Impairments{.trace = trace_of(every(10, 10, 100)), .queue_limit_packets = 5});
  Arrivals arrivals;
  arrivals.attach(link, executor);
  std::vector<LinkEvent> drops;
  auto subscription = link.events().subscribe([&](const Event& event) {
    if (const auto* link_event = std::get_if<LinkEvent>(&event.body); link_event && link_event->outcome == LinkOutcome::dropped) {
      drops.push_back(*link_event);
    }
  });
  for (std::uint64_t i = 1; i <= 3; ++i) link.send(frame_of_wire_size(i, 3000));  // 2 packets each
  executor.run_for(1s);
  ASSERT_EQ(drops.size(), 1u);
  EXPECT_EQ(drops[0].reason, DropReason::queue_full);
  EXPECT_EQ(drops[0].message_id, 3u);
  const auto& counters = link.counters();
  EXPECT_EQ(counters.sent, 3u);
  EXPECT_EQ(counters.delivered, 2u);
  EXPECT_EQ(counters.dropped, 1u);
  EXPECT_EQ(arrivals.list.back().second, SimTime{40'000});
}

TEST(TraceLink, QueueLimitInBytes) {
  VirtualExecutor executor;
  LinkDirection link(executor, 1);
  link.set_impairments(Impairments{.queue_limit_bytes = 5000, .trace = trace_of(every(10, 10, 100))});
  link.send(frame_of_wire_size(1, 3000));
  link.send(frame_of_wire_size(2, 2000));   // 5000: fits exactly
  link.send(frame_of_wire_size(3, 100));    // over
  executor.run_until(SimTime{10'000});      // the first packet (1500 B) leaves
  link.send(frame_of_wire_size(4, 1500));   // 3500 + 1500: fits again
  executor.run_for(1s);
  EXPECT_EQ(link.counters().delivered, 3u);
  EXPECT_EQ(link.counters().dropped, 1u);
}

TEST(TraceLink, TheTraceWrapsAroundAtItsEnd) {
  VirtualExecutor executor;
  LinkDirection link(executor, 1);
  link.set_impairments(Impairments{.trace = trace_of("10\n20\n")});
  Arrivals arrivals;
  arrivals.attach(link, executor);
  executor.run_until(SimTime{25'000});
  link.send(frame_of_wire_size(1, 100));   // the second loop's first opportunity: 30 ms
  executor.run_until(SimTime{1'000'500});
  link.send(frame_of_wire_size(2, 100));   // loop 50 starts at 1000 ms: 1010 ms
  executor.run_for(1s);
  EXPECT_EQ(arrivals.list, (std::vector<std::pair<std::uint64_t, SimTime>>{{1, SimTime{30'000}}, {2, SimTime{1'010'000}}}));
}

TEST(TraceLink, ATraceStartsWhenItIsSetAndSurvivesOtherChanges) {
  VirtualExecutor executor;
  LinkDirection link(executor, 1);
  executor.run_until(SimTime{7'000});
  Impairments impairments{.trace = trace_of("10\n")};
  link.set_impairments(impairments);          // opportunities at 17, 27, … ms
  executor.run_until(SimTime{20'000});
  impairments.delay = 1ms;
  link.set_impairments(impairments);          // same trace: same timetable
  Arrivals arrivals;
  arrivals.attach(link, executor);
  link.send(frame_of_wire_size(1, 100));
  executor.run_for(1s);
  ASSERT_EQ(arrivals.list.size(), 1u);
  EXPECT_EQ(arrivals.list[0].second, SimTime{28'000});
}

TEST(TraceLink, ZeroCapacityGapHoldsTheQueueAndLossCombines) {
  // A tunnel: nothing between 100 ms and 4100 ms. With random loss, every message is still
  // accounted for: sent = delivered + dropped + in flight, at every moment.
  std::string text = every(1, 1, 100) + every(1, 4100, 5000);
  VirtualExecutor executor;
  LinkDirection link(executor, 3);
  link.set_impairments(Impairments{.delay = 20ms, .loss_probability = 0.1, .trace = trace_of(text),
                                   .queue_limit_packets = 300});
  Arrivals arrivals;
  arrivals.attach(link, executor);
  for (int i = 0; i < 1000; ++i) {
    executor.call_at(SimTime{i * 5000}, [&, i] {
      link.send(frame_of_wire_size(static_cast<std::uint64_t>(i), 1200));
      const auto& counters = link.counters();
      ASSERT_EQ(counters.sent, counters.delivered + counters.dropped + counters.in_flight);
    });
  }
  executor.run_until(SimTime{4'000'000});
  for (const auto& arrival : arrivals.list) EXPECT_LE(arrival.second, SimTime{120'000});
  executor.run_for(10s);
  const auto& counters = link.counters();
  EXPECT_EQ(counters.sent, 1000u);
  EXPECT_EQ(counters.sent, counters.delivered + counters.dropped);
  EXPECT_EQ(counters.in_flight, 0u);
  EXPECT_GT(counters.dropped, 100u);   // random loss and the queue filling in the tunnel
}

}  // namespace
}  // namespace ocp
