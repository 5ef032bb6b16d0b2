// Link recordings (ocp/link_recording.hpp) and their replay on a LinkDirection
// (Impairments::replay): the n-th message gets the n-th recorded outcome, looping, exactly.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "ocp/com_channel.hpp"
#include "ocp/link_recording.hpp"
#include "ocp/virtual_executor.hpp"

namespace ocp {
namespace {

std::shared_ptr<const LinkRecording> recording_of(const std::string& text) {
  auto recording = LinkRecording::parse(text, "test.link");
  EXPECT_TRUE(recording.ok()) << (recording.ok() ? "" : recording.error().detail);
  return std::make_shared<const LinkRecording>(std::move(recording).value());
}

std::string parse_error(const std::string& text) {
  auto recording = LinkRecording::parse(text, "bad.link");
  return recording.ok() ? "parsed" : recording.error().detail;
}

// A ping every 10 ms from 0; the arrival time of each, or -1 when it never arrives.
std::vector<std::int64_t> arrivals_of(LinkDirection& link, VirtualExecutor& executor, int count) {
  std::vector<std::int64_t> arrivals(static_cast<std::size_t>(count), -1);
  link.set_receiver([&](LinkMessage&& message) {
    arrivals[std::get<Ping>(message).id] = executor.now().count();
  });
  for (int i = 0; i < count; ++i) {
    executor.call_at(SimTime{i * 10'000}, [&link, i] { link.send(Ping{static_cast<std::uint64_t>(i), SimTime{0}}); });
  }
  executor.run_until(SimTime{10'000'000});
  return arrivals;
}

TEST(LinkRecording, EachMessageGetsItsRecordedDelayOrLossAndTheRecordingLoops) {
  VirtualExecutor executor;
  LinkDirection link(executor, 1);
  link.set_identity("truck-1", LinkRoute::to_streamer);
  link.set_impairments(Impairments{.replay = recording_of(
      "# a comment\nocp-link-recording 1\nto_streamer 0 30000\nto_streamer 10000 lost\n"
      "to_streamer 20000 5000   # overtakes the first\nto_player 0 1\n")});
  const auto arrivals = arrivals_of(link, executor, 7);
  EXPECT_EQ(arrivals, (std::vector<std::int64_t>{30'000, -1, 25'000, 60'000, -1, 55'000, 90'000}));
  EXPECT_EQ(link.counters().dropped, 2u);
}

TEST(LinkRecording, TheOtherRouteIsUsedOnTheOtherDirection) {
  VirtualExecutor executor;
  LinkDirection link(executor, 1);
  link.set_identity("truck-1", LinkRoute::to_player);
  link.set_impairments(Impairments{.replay = recording_of("ocp-link-recording 1\nto_streamer 0 lost\nto_player 0 7000\n")});
  EXPECT_EQ(arrivals_of(link, executor, 2), (std::vector<std::int64_t>{7'000, 17'000}));
}

TEST(LinkRecording, AnOutageStillDropsAndUsesUpItsEntry) {
  VirtualExecutor executor;
  LinkDirection link(executor, 1);
  link.set_impairments(Impairments{.replay = recording_of("ocp-link-recording 1\nto_streamer 0 1000\nto_streamer 0 2000\n")});
  executor.call_at(SimTime{0}, [&] { link.outage_for(Micros{5'000}); });
  // Message 0 is lost to the outage; message 1 gets entry 1 (2 ms), message 2 entry 0 (1 ms).
  EXPECT_EQ(arrivals_of(link, executor, 3), (std::vector<std::int64_t>{-1, 12'000, 21'000}));
}

TEST(LinkRecording, ANewRecordingStartsFromItsFirstMessage) {
  VirtualExecutor executor;
  LinkDirection link(executor, 1);
  const auto one = recording_of("ocp-link-recording 1\nto_streamer 0 1000\nto_streamer 0 2000\n");
  link.set_impairments(Impairments{.replay = one});
  executor.call_at(SimTime{15'000}, [&] { link.set_impairments(Impairments{.replay = recording_of(
                                              "ocp-link-recording 1\nto_streamer 0 3000\nto_streamer 0 4000\n")}); });
  EXPECT_EQ(arrivals_of(link, executor, 3), (std::vector<std::int64_t>{1'000, 12'000, 23'000}));
}

TEST(LinkRecording, FormatReadsBack) {
  const auto recording = recording_of("ocp-link-recording 1\nclock to_player rtt_half\nto_player 5 lost\nto_player 9 12\n");
  const std::string text = recording->format({"hello"});
  EXPECT_EQ(text, "# hello\nocp-link-recording 1\nclock to_streamer measured\nclock to_player rtt_half\n"
                  "to_player 5 lost\nto_player 9 12\n");
  EXPECT_EQ(recording_of(text)->format({"hello"}), text);
}

TEST(LinkRecording, BadInputNamesTheFileAndLine) {
  EXPECT_EQ(parse_error(""), "bad.link: empty link recording (no header, no messages)");
  EXPECT_EQ(parse_error("ocp-link-recording 1\n\n"), "bad.link: empty link recording (no messages)");
  EXPECT_EQ(parse_error("12\n"), "bad.link:1: expected the header 'ocp-link-recording 1' (is this a link recording?)");
  EXPECT_EQ(parse_error("ocp-link-recording 2\n"), "bad.link:1: unsupported link recording version 2 (this build reads 1)");
  EXPECT_EQ(parse_error("ocp-link-recording 1\nto_somewhere 0 1\n"),
            "bad.link:2: expected to_streamer, to_player or clock, got 'to_somewhere'");
  EXPECT_EQ(parse_error("ocp-link-recording 1\nto_player 0 x\n"),
            "bad.link:2: expected a delay in whole microseconds up to 3600000000, or 'lost', got 'x'");
  EXPECT_EQ(parse_error("ocp-link-recording 1\nto_player 9 1\nto_player 8 1\n"),
            "bad.link:3: send time 8 goes backwards (the previous to_player message was sent at 9)");
  EXPECT_EQ(parse_error("ocp-link-recording 1\nclock to_player sometimes\n"),
            "bad.link:2: unknown clock 'sometimes' (measured or rtt_half)");
  EXPECT_EQ(parse_error("ocp-link-recording 1\nto_player 1\n"),
            "bad.link:2: expected 'ROUTE SENT_US DELAY_US' or 'ROUTE SENT_US lost'");
}

}  // namespace
}  // namespace ocp
