// LinkHandover (world/src/link_handover.hpp): link messages crossing to another thread's part of
// the World. The "thread" here is a list of posted tasks the test runs by hand.
#include <gtest/gtest.h>

#include <functional>
#include <vector>

#include "link_handover.hpp"

namespace ocp {
namespace {

struct Harness {
  std::vector<std::function<void()>> posted;
  std::vector<std::uint64_t> delivered;   // ping sequence numbers, in delivery order
  std::vector<std::uint64_t> overflow_reports;
  LinkHandover handover{[this](std::function<void()> task) { posted.push_back(std::move(task)); },
                        [this](HandedMessage&& handed) { delivered.push_back(std::get<Ping>(handed.message).id); },
                        [this](std::uint64_t dropped) { overflow_reports.push_back(dropped); }, /*max_queued=*/3};

  void push(std::uint64_t sequence) { handover.push(HandedMessage{ToStreamer{nullptr}, Ping{sequence, {}}}); }
  void run_posted() {
    auto tasks = std::move(posted);
    posted.clear();
    for (auto& task : tasks) task();
  }
};

TEST(LinkHandover, PostsOneTaskPerBatchAndDeliversInOrder) {
  Harness harness;
  harness.push(1);
  harness.push(2);
  EXPECT_EQ(harness.posted.size(), 1u);
  harness.run_posted();
  EXPECT_EQ(harness.delivered, (std::vector<std::uint64_t>{1, 2}));
  harness.push(3);
  EXPECT_EQ(harness.posted.size(), 1u);   // a new batch, a new wake-up
  harness.run_posted();
  EXPECT_EQ(harness.delivered, (std::vector<std::uint64_t>{1, 2, 3}));
  EXPECT_TRUE(harness.overflow_reports.empty());
}

TEST(LinkHandover, DropsBeyondItsLimitAndSaysSoOnceAtTheStartAndOnceWithTheCount) {
  Harness harness;
  for (std::uint64_t sequence = 1; sequence <= 5; ++sequence) harness.push(sequence);   // 4 and 5 dropped
  harness.run_posted();
  EXPECT_EQ(harness.delivered, (std::vector<std::uint64_t>{1, 2, 3}));
  EXPECT_EQ(harness.overflow_reports, (std::vector<std::uint64_t>{0}));   // started

  for (std::uint64_t sequence = 6; sequence <= 9; ++sequence) harness.push(sequence);   // 9 dropped
  harness.run_posted();
  EXPECT_EQ(harness.overflow_reports, (std::vector<std::uint64_t>{0}));   // same episode: silent

  harness.push(10);
  harness.run_posted();   // nothing dropped since: the episode ends with its count
  EXPECT_EQ(harness.delivered, (std::vector<std::uint64_t>{1, 2, 3, 6, 7, 8, 10}));
  EXPECT_EQ(harness.overflow_reports, (std::vector<std::uint64_t>{0, 3}));
}

}  // namespace
}  // namespace ocp
