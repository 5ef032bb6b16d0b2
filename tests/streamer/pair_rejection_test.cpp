// Why the loop does not close (issue #20): the first rejected returned pair of an InvalidMac
// episode is logged and published once, naming the pair the Streamer issued and a hint; the
// next episode (after a valid pair) is reported again. In virtual time.
#include <fmt/format.h>

#include <algorithm>

#include "streamer_harness.hpp"

namespace ocp::streamer_test {
namespace {

constexpr std::uint64_t two_to_53 = std::uint64_t{1} << 53;

struct Rejection {
  SimTime at;
  AckPair rejected;
  PairJudgement judgement;
  std::string hint;
};

class RejectionRecorder {
 public:
  explicit RejectionRecorder(EventBus& events)
      : subscription_(events.subscribe([this](const Event& event) {
          if (const auto* rejected = std::get_if<PairRejected>(&event.body)) {
            seen.push_back({event.time, rejected->rejected, rejected->judgement, std::string(rejected->hint)});
          }
        })) {}
  std::vector<Rejection> seen;

 private:
  EventBus::Subscription subscription_;
};

std::size_t warnings_containing(const testing::CapturedLog& log, std::string_view needle) {
  return static_cast<std::size_t>(std::count_if(log.lines().begin(), log.lines().end(), [&](const auto& line) {
    return line.level == LogLevel::warn && line.message.find(needle) != std::string::npos;
  }));
}

// The operator returns pairs issued 5 ms before each message; between `bad_from` and `bad_to`
// their ack_time is one more than issued, as a client that reads it as a double would make
// an odd value above 2^53.
OperatorControl control_at(StreamerHarness& harness, SimTime now, std::vector<std::pair<SimTime, SimTime>> bad) {
  AckPair pair = harness.pair_issued_at(now - ms(5));
  for (const auto& [from, to] : bad) {
    if (now >= from && now < to) pair.ack_time += 1;
  }
  return harness.control_returning(pair);
}

TEST(StreamerPairRejection, OffByOneIsToldOnceAnEpisodeWithTheIssuedPairAndTheHint) {
  StreamerConfig config = test_config();
  config.ack_time_offset = two_to_53 + 1;   // odd: a double cannot hold it
  StreamerHarness harness(config);
  RejectionRecorder recorder(harness.core.events());
  harness.connect_vehicle();
  harness.core.start();
  const std::vector<std::pair<SimTime, SimTime>> bad{{ms(205), ms(405)}, {ms(605), ms(705)}};
  harness.schedule_controls(ms(5), ms(995), Micros{10'000},
                            [&](SimTime now) { return control_at(harness, now, bad); });
  harness.executor.run_until(ms(1000));

  // Two episodes of 20 and 10 rejected pairs: two reports, each at the episode's first pair.
  ASSERT_EQ(recorder.seen.size(), 2u);
  EXPECT_EQ(recorder.seen[0].at, ms(205));
  EXPECT_EQ(recorder.seen[1].at, ms(605));
  const AckPair issued = harness.pair_issued_at(ms(200));
  const Rejection& first = recorder.seen[0];
  EXPECT_EQ(first.rejected.ack_time, issued.ack_time + 1);
  EXPECT_EQ(first.judgement.cause, PairCause::rounded_through_double);
  ASSERT_TRUE(first.judgement.nearest_issued);
  EXPECT_EQ(*first.judgement.nearest_issued, issued);
  EXPECT_NE(first.hint.find(fmt::format("ack_time differs by 1 from issued pair (ack_time {}, ack_time_mac {})",
                                        issued.ack_time, issued.ack_time_mac)),
            std::string::npos)
      << first.hint;
  EXPECT_NE(first.hint.find("rounded through a double?"), std::string::npos) << first.hint;

  // The log says the first episode in full, once, not once a rejected pair; the second, within
  // the summary period, is only counted (the log must not flood: see the next test).
  EXPECT_EQ(warnings_containing(harness.log, "latency loop not closed (InvalidMac)"), 1u);
  EXPECT_TRUE(harness.log.contains(LogLevel::warn, first.hint));
  // The fault itself follows every pair, as before.
  EXPECT_EQ(harness.observer.changes(FaultId::InvalidMac, true), (std::vector<SimTime>{ms(205), ms(605)}));
  EXPECT_EQ(harness.observer.changes(FaultId::InvalidMac, false), (std::vector<SimTime>{ms(405), ms(705)}));
}

// A client alternating a good and a made-up pair opens an episode every other message (100 a
// second at the 100 Hz control rate, as does a replay beside a live session): the first is told
// in full, the rest summarised every 5 s (before this rule: 3 000 lines in this minute).
TEST(StreamerPairRejection, AlternatingGoodAndBadPairsDoNotFloodTheLog) {
  StreamerHarness harness;
  RejectionRecorder recorder(harness.core.events());
  harness.connect_vehicle();
  harness.core.start();
  bool bad = false;
  harness.schedule_controls(ms(5), ms(60'000), Micros{10'000}, [&](SimTime now) {
    AckPair pair = harness.pair_issued_at(now - ms(5));
    if ((bad = !bad)) pair.ack_time_mac ^= 1u;
    return harness.control_returning(pair);
  });
  harness.executor.run_until(ms(70'000));
  EXPECT_EQ(recorder.seen.size(), 3000u);   // the event stream still sees every episode
  EXPECT_EQ(warnings_containing(harness.log, "latency loop not closed (InvalidMac): "), 1u);
  const std::size_t summaries = warnings_containing(harness.log, "latency loop not closed (InvalidMac) again: ");
  EXPECT_GE(summaries, 12u);
  EXPECT_LE(summaries, 13u);   // 60 s / 5 s, and one for the last few
}

TEST(StreamerPairRejection, MissingPairsAreNotJudgedAndDoNotEndAnEpisode) {
  StreamerHarness harness;
  RejectionRecorder recorder(harness.core.events());
  harness.connect_vehicle();
  harness.core.start();
  harness.executor.run_until(ms(100));
  AckPair altered = harness.pair_issued_at(ms(50));
  altered.ack_time_mac ^= 1u;
  harness.send_control(harness.control_returning(std::nullopt));   // nothing to compare: no report
  EXPECT_TRUE(recorder.seen.empty());
  harness.send_control(harness.control_returning(altered));
  harness.send_control(harness.control_returning(std::nullopt));
  harness.send_control(harness.control_returning(altered));
  ASSERT_EQ(recorder.seen.size(), 1u);
  EXPECT_EQ(recorder.seen[0].judgement.cause, PairCause::mac_altered);
  EXPECT_NE(recorder.seen[0].hint.find("MAC altered"), std::string::npos) << recorder.seen[0].hint;
}

TEST(StreamerPairRejection, AnotherStreamersPairIsCalledStale) {
  StreamerHarness harness;
  RejectionRecorder recorder(harness.core.events());
  harness.connect_vehicle();
  harness.core.start();
  harness.executor.run_until(ms(100));
  harness.send_control(harness.control_returning(AckPair{55'555, 0x1234u}));   // never issued here
  ASSERT_EQ(recorder.seen.size(), 1u);
  EXPECT_EQ(recorder.seen[0].judgement.cause, PairCause::not_issued);
  EXPECT_NE(recorder.seen[0].hint.find("stale pair"), std::string::npos) << recorder.seen[0].hint;
}

}  // namespace
}  // namespace ocp::streamer_test
