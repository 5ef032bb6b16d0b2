#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "ocp/com_channel.hpp"
#include "ocp/virtual_executor.hpp"

namespace ocp {
namespace {

using namespace std::chrono_literals;

Ping ping(std::uint64_t id) { return Ping{id, SimTime{0}}; }

// A video frame whose estimated wire size is exactly `wire_bytes`.
VideoFrame frame_of_wire_size(std::uint64_t number, std::size_t wire_bytes) {
  VideoFrame frame{"front", number, std::nullopt, 0};
  frame.size_bytes = static_cast<std::uint32_t>(wire_bytes - wire_size_bytes(frame));
  return frame;
}

std::uint64_t id_of(const LinkMessage& message) {
  if (const auto* as_ping = std::get_if<Ping>(&message)) {
    return as_ping->id;
  }
  return std::get<VideoFrame>(message).frame_number;
}

// Collects (id, arrival time) of everything one direction delivers.
struct Arrivals {
  std::vector<std::pair<std::uint64_t, SimTime>> list;
  void attach(LinkDirection& direction, const Executor& executor) {
    direction.set_receiver([this, &executor](LinkMessage&& message) { list.emplace_back(id_of(message), executor.now()); });
  }
  std::vector<std::uint64_t> ids() const {
    std::vector<std::uint64_t> result;
    for (const auto& arrival : list) {
      result.push_back(arrival.first);
    }
    return result;
  }
  std::vector<SimTime> times() const {
    std::vector<SimTime> result;
    for (const auto& arrival : list) {
      result.push_back(arrival.second);
    }
    return result;
  }
};

// Sends `count` pings 1 ms apart through a fresh link with `impairments` and `seed`.
std::vector<std::pair<std::uint64_t, SimTime>> run_link(const Impairments& impairments, std::uint64_t seed,
                                                        int count = 1000) {
  VirtualExecutor executor;
  ComChannel channel(executor, seed);
  channel.to_streamer().set_impairments(impairments);
  Arrivals arrivals;
  arrivals.attach(channel.to_streamer(), executor);
  for (int i = 0; i < count; ++i) {
    executor.call_at(SimTime{i * 1000}, [&, i] { channel.to_streamer().send(ping(static_cast<std::uint64_t>(i))); });
  }
  executor.run_for(1h);
  return arrivals.list;
}

TEST(ComChannel, FixedDelayDeliversAtExactTimes) {
  VirtualExecutor executor;
  ComChannel channel(executor, 1);
  channel.to_streamer().set_impairments(Impairments{.delay = 40ms});
  Arrivals arrivals;
  arrivals.attach(channel.to_streamer(), executor);
  channel.to_streamer().send(ping(1));
  executor.run_until(SimTime{2500});
  channel.to_streamer().send(ping(2));
  EXPECT_EQ(channel.to_streamer().counters().in_flight, 2u);
  executor.run_until(SimTime{39'999});
  EXPECT_TRUE(arrivals.list.empty());
  executor.run_for(1s);
  EXPECT_EQ(arrivals.times(), (std::vector<SimTime>{SimTime{40'000}, SimTime{42'500}}));
  const auto& counters = channel.to_streamer().counters();
  EXPECT_EQ(counters.sent, 2u);
  EXPECT_EQ(counters.delivered, 2u);
  EXPECT_EQ(counters.in_flight, 0u);
  EXPECT_EQ(counters.bytes_sent, 2 * wire_size_bytes(ping(1)));
  EXPECT_EQ(counters.bytes_delivered, counters.bytes_sent);
}

TEST(ComChannel, DirectionsAreIndependent) {
  VirtualExecutor executor;
  ComChannel channel(executor, 1, "truck-1");
  channel.to_streamer().set_impairments(Impairments{.delay = 10ms});
  channel.to_player().set_impairments(Impairments{.delay = 30ms});
  Arrivals at_streamer;
  Arrivals at_player;
  at_streamer.attach(channel.to_streamer(), executor);
  at_player.attach(channel.to_player(), executor);
  channel.to_streamer().send(ping(1));
  channel.to_player().send(ping(2));
  executor.run_for(1s);
  EXPECT_EQ(at_streamer.times(), std::vector<SimTime>{SimTime{10'000}});
  EXPECT_EQ(at_player.times(), std::vector<SimTime>{SimTime{30'000}});
  EXPECT_EQ(channel.name(), "truck-1");
}

TEST(ComChannel, UniformJitterStaysInBoundsKeepsOrderAndIsSeedDeterministic) {
  const Impairments impairments{.delay = 40ms, .jitter_kind = Impairments::JitterKind::uniform, .jitter = 5ms};
  const auto first = run_link(impairments, 7);
  const auto again = run_link(impairments, 7);
  const auto other = run_link(impairments, 8);
  EXPECT_EQ(first, again);
  EXPECT_NE(first, other);
  ASSERT_EQ(first.size(), 1000u);
  bool some_early = false;
  bool some_late = false;
  for (std::size_t i = 0; i < first.size(); ++i) {
    ASSERT_EQ(first[i].first, i);  // FIFO despite jitter
    const SimTime sent_at{static_cast<std::int64_t>(i) * 1000};
    const Micros delay = first[i].second - sent_at;
    ASSERT_LE(delay, 45ms);
    // Clamping to the predecessor can only make a message later, never earlier than 35 ms.
    ASSERT_GE(delay, 35ms);
    some_early = some_early || delay < 37ms;
    some_late = some_late || delay > 43ms;
  }
  EXPECT_TRUE(some_early);
  EXPECT_TRUE(some_late);
}

TEST(ComChannel, NormalJitterNeverGivesNegativeDelay) {
  const Impairments impairments{.delay = 1ms, .jitter_kind = Impairments::JitterKind::normal, .jitter = 5ms};
  const auto arrivals = run_link(impairments, 3);
  ASSERT_EQ(arrivals.size(), 1000u);
  for (std::size_t i = 0; i < arrivals.size(); ++i) {
    ASSERT_GE(arrivals[i].second, SimTime{static_cast<std::int64_t>(i) * 1000});
  }
  EXPECT_EQ(arrivals, run_link(impairments, 3));
}

TEST(ComChannel, NormalJitterHasTheRequestedSpread) {
  // One message per second, so FIFO clamping never interferes with the raw samples.
  VirtualExecutor executor;
  LinkDirection direction(executor, 99);
  direction.set_impairments(Impairments{.delay = 100ms, .jitter_kind = Impairments::JitterKind::normal, .jitter = 10ms});
  std::vector<double> delays_ms;
  direction.set_receiver([&](LinkMessage&& message) {
    const auto& sent = std::get<Ping>(message);
    delays_ms.push_back(static_cast<double>((executor.now() - sent.sent_at).count()) / 1000.0);
  });
  for (int i = 0; i < 4000; ++i) {
    executor.call_at(SimTime{i * 1'000'000LL}, [&, i] { direction.send(Ping{static_cast<std::uint64_t>(i), executor.now()}); });
  }
  executor.run_for(std::chrono::hours{2});
  ASSERT_EQ(delays_ms.size(), 4000u);
  double sum = 0.0;
  for (double delay : delays_ms) {
    sum += delay;
  }
  const double mean = sum / static_cast<double>(delays_ms.size());
  double squares = 0.0;
  for (double delay : delays_ms) {
    squares += (delay - mean) * (delay - mean);
  }
  const double deviation = std::sqrt(squares / static_cast<double>(delays_ms.size()));
  EXPECT_NEAR(mean, 100.0, 1.0);
  EXPECT_NEAR(deviation, 10.0, 1.0);
}

TEST(ComChannel, RandomLossDropsAboutTheRequestedFraction) {
  const auto arrivals = run_link(Impairments{.loss_probability = 0.1}, 11, 10000);
  const double lost = 1.0 - static_cast<double>(arrivals.size()) / 10000.0;
  EXPECT_GT(lost, 0.08);
  EXPECT_LT(lost, 0.12);
  EXPECT_EQ(arrivals, run_link(Impairments{.loss_probability = 0.1}, 11, 10000));
}

TEST(ComChannel, LossCountsAsDropped) {
  VirtualExecutor executor;
  LinkDirection direction(executor, 5);
  direction.set_impairments(Impairments{.loss_probability = 1.0});
  direction.send(ping(1));
  executor.run_for(1s);
  EXPECT_EQ(direction.counters().sent, 1u);
  EXPECT_EQ(direction.counters().dropped, 1u);
  EXPECT_EQ(direction.counters().delivered, 0u);
}

TEST(ComChannel, BurstLossProducesRunsOfLosses) {
  Impairments impairments{.burst_loss = true,
                          .good_to_bad_probability = 0.01,
                          .bad_to_good_probability = 0.1,
                          .loss_in_good = 0.0,
                          .loss_in_bad = 1.0};
  const auto arrivals = run_link(impairments, 21, 10000);
  std::vector<bool> received(10000, false);
  for (const auto& arrival : arrivals) {
    received[arrival.first] = true;
  }
  std::size_t runs = 0;
  std::size_t lost = 0;
  std::size_t longest_run = 0;
  std::size_t current_run = 0;
  for (bool got : received) {
    if (got) {
      current_run = 0;
      continue;
    }
    ++lost;
    if (current_run++ == 0) {
      ++runs;
    }
    longest_run = std::max(longest_run, current_run);
  }
  ASSERT_GT(runs, 20u);
  // Mean bad-state sojourn is 1 / 0.1 = 10 messages; independent loss at the same rate
  // (~9 %) would give runs averaging ~1.1.
  const double mean_run = static_cast<double>(lost) / static_cast<double>(runs);
  EXPECT_GT(mean_run, 5.0);
  EXPECT_GE(longest_run, 20u);
}

TEST(ComChannel, BandwidthCapSerialisesMessagesInOrder) {
  VirtualExecutor executor;
  LinkDirection direction(executor, 1);
  direction.set_impairments(Impairments{.bandwidth_bits_per_second = 1e6});
  Arrivals arrivals;
  arrivals.attach(direction, executor);
  for (std::uint64_t i = 0; i < 10; ++i) {
    direction.send(frame_of_wire_size(i, 1250));  // 10 000 bits = 10 ms at 1 Mbit/s
  }
  EXPECT_EQ(direction.counters().queue_depth_bytes, 12'500u);
  executor.run_until(SimTime{35'000});
  EXPECT_EQ(direction.counters().queue_depth_bytes, 8'125u);  // 65 ms of 1 Mbit/s still queued
  executor.run_for(1s);
  std::vector<SimTime> expected;
  for (int i = 1; i <= 10; ++i) {
    expected.push_back(SimTime{i * 10'000});
  }
  EXPECT_EQ(arrivals.times(), expected);
  EXPECT_EQ(arrivals.ids(), (std::vector<std::uint64_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
  EXPECT_EQ(direction.counters().queue_depth_bytes, 0u);
}

TEST(ComChannel, BandwidthQueueAddsToTheFixedDelay) {
  VirtualExecutor executor;
  LinkDirection direction(executor, 1);
  direction.set_impairments(Impairments{.delay = 40ms, .bandwidth_bits_per_second = 1e6});
  Arrivals arrivals;
  arrivals.attach(direction, executor);
  direction.send(frame_of_wire_size(0, 1250));
  direction.send(frame_of_wire_size(1, 1250));
  executor.run_for(1s);
  EXPECT_EQ(arrivals.times(), (std::vector<SimTime>{SimTime{50'000}, SimTime{60'000}}));
}

TEST(ComChannel, QueueLimitTailDrops) {
  VirtualExecutor executor;
  LinkDirection direction(executor, 1);
  direction.set_impairments(Impairments{.bandwidth_bits_per_second = 1e6, .queue_limit_bytes = 5000});
  Arrivals arrivals;
  arrivals.attach(direction, executor);
  for (std::uint64_t i = 0; i < 10; ++i) {
    direction.send(frame_of_wire_size(i, 1250));
  }
  executor.run_for(1s);
  EXPECT_EQ(arrivals.ids(), (std::vector<std::uint64_t>{0, 1, 2, 3}));
  EXPECT_EQ(direction.counters().dropped, 6u);
  EXPECT_EQ(direction.counters().delivered, 4u);
}

TEST(ComChannel, DuplicationDeliversExtraCopies) {
  VirtualExecutor executor;
  LinkDirection direction(executor, 4);
  direction.set_impairments(Impairments{.duplicate_probability = 0.25});
  Arrivals arrivals;
  arrivals.attach(direction, executor);
  for (std::uint64_t i = 0; i < 4000; ++i) {
    direction.send(ping(i));
  }
  executor.run_for(1s);
  const auto& counters = direction.counters();
  EXPECT_GT(counters.duplicated, 800u);
  EXPECT_LT(counters.duplicated, 1200u);
  EXPECT_EQ(counters.delivered, 4000u + counters.duplicated);
  EXPECT_EQ(arrivals.list.size(), counters.delivered);
}

TEST(ComChannel, ReorderingLetsLaterMessagesOvertake) {
  const auto arrivals = run_link(Impairments{.delay = 10ms, .reorder_probability = 0.2, .reorder_extra_delay = 5ms}, 17);
  ASSERT_EQ(arrivals.size(), 1000u);
  std::size_t inversions = 0;
  for (std::size_t i = 1; i < arrivals.size(); ++i) {
    inversions += arrivals[i].first < arrivals[i - 1].first ? 1 : 0;
  }
  EXPECT_GT(inversions, 50u);
  for (const auto& [id, at] : arrivals) {
    const Micros delay = at - SimTime{static_cast<std::int64_t>(id) * 1000};
    ASSERT_TRUE(delay == 10ms || delay == 15ms) << delay.count();
  }
}

TEST(ComChannel, OutageDropsExactlyTheMessagesSentWhileDown) {
  VirtualExecutor executor;
  LinkDirection direction(executor, 1);
  direction.set_impairments(Impairments{.delay = 20ms});
  Arrivals arrivals;
  arrivals.attach(direction, executor);
  // Sends at 300 … 490 ms fall inside [300 ms, 500 ms); messages in flight at 300 ms arrive.
  executor.call_at(SimTime{300'000}, [&] { direction.outage_for(200ms); });
  for (int i = 0; i < 100; ++i) {
    executor.call_at(SimTime{i * 10'000}, [&, i] { direction.send(ping(static_cast<std::uint64_t>(i))); });
  }
  executor.run_for(2s);
  std::vector<std::uint64_t> expected;
  for (std::uint64_t i = 0; i < 100; ++i) {
    if (i < 30 || i >= 50) {
      expected.push_back(i);
    }
  }
  EXPECT_EQ(arrivals.ids(), expected);
  EXPECT_EQ(direction.counters().dropped, 20u);
}

TEST(ComChannel, DownFlagDropsUntilCleared) {
  VirtualExecutor executor;
  LinkDirection direction(executor, 1);
  Arrivals arrivals;
  arrivals.attach(direction, executor);
  direction.set_impairments(Impairments{.down = true});
  direction.send(ping(1));
  Impairments up = direction.impairments();
  up.down = false;
  direction.set_impairments(up);
  direction.send(ping(2));
  executor.run_for(1s);
  EXPECT_EQ(arrivals.ids(), std::vector<std::uint64_t>{2});
}

TEST(ComChannel, ChangingImpairmentsMidRunAppliesToLaterSends) {
  VirtualExecutor executor;
  LinkDirection direction(executor, 1);
  direction.set_impairments(Impairments{.delay = 100ms});
  Arrivals arrivals;
  arrivals.attach(direction, executor);
  direction.send(ping(1));
  executor.run_until(SimTime{10'000});
  direction.set_impairments(Impairments{.delay = 10ms});
  direction.send(ping(2));
  executor.run_for(1s);
  // The first message keeps its 100 ms; the second is held behind it (FIFO without reordering).
  EXPECT_EQ(arrivals.list, (std::vector<std::pair<std::uint64_t, SimTime>>{{1, SimTime{100'000}}, {2, SimTime{100'000}}}));
  direction.send(ping(3));
  executor.run_for(1s);
  EXPECT_EQ(arrivals.list.back(), std::make_pair(std::uint64_t{3}, SimTime{1'020'000}));
}

TEST(ComChannel, DestroyingADirectionWithMessagesInFlightIsSafe) {
  VirtualExecutor executor;
  int received = 0;
  {
    LinkDirection direction(executor, 1);
    direction.set_impairments(Impairments{.delay = 10ms});
    direction.set_receiver([&](LinkMessage&&) { ++received; });
    direction.send(ping(1));
  }
  executor.run_for(1s);
  EXPECT_EQ(received, 0);
}

TEST(ComChannel, SameSeedGivesIdenticalRunsWithEveryImpairment) {
  const Impairments impairments{.delay = 30ms,
                                .jitter_kind = Impairments::JitterKind::normal,
                                .jitter = 4ms,
                                .loss_probability = 0.02,
                                .burst_loss = true,
                                .good_to_bad_probability = 0.01,
                                .bad_to_good_probability = 0.3,
                                .bandwidth_bits_per_second = 2e6,
                                .queue_limit_bytes = 20'000,
                                .duplicate_probability = 0.01,
                                .reorder_probability = 0.05,
                                .reorder_extra_delay = 7ms};
  EXPECT_EQ(run_link(impairments, 1234, 5000), run_link(impairments, 1234, 5000));
  EXPECT_NE(run_link(impairments, 1234, 5000), run_link(impairments, 4321, 5000));
}

}  // namespace
}  // namespace ocp
