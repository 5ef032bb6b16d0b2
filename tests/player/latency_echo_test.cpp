// The latency-loop echo (SPEC §5 step 6) and client data source locking (SPEC §4.3).
#include <gtest/gtest.h>

#include "player_harness.hpp"

namespace ocp::testing {
namespace {

constexpr AckPair first_pair{1'000, 111};
constexpr AckPair second_pair{9'007'199'254'740'993ULL, 222};  // 2^53 + 1: must stay exact

ClientVehicleEntry echo_entry(AckPair pair, std::optional<std::string> user_data = std::nullopt) {
  ClientVehicleEntry entry;
  entry.ack_time_returned = pair.ack_time;
  entry.ack_time_mac_returned = pair.ack_time_mac;
  if (user_data) entry.user_data = RawJson{*user_data};
  return entry;
}

TEST(Player, SelfEchoReturnsTheLatestSeiPair) {
  PlayerHarness harness;
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.start();
  harness.video_at(at_ms(12), "truck-1", first_pair);
  harness.video_at(at_ms(25), "truck-1", second_pair, "rear");
  harness.video_at(at_ms(33), "truck-1", std::nullopt);  // a frame without SEI keeps the pair
  harness.run_until(at_ms(40));
  EXPECT_EQ(harness.control_at("truck-1", at_ms(10))->returned_ack, std::nullopt);
  EXPECT_EQ(harness.control_at("truck-1", at_ms(20))->returned_ack, first_pair);
  EXPECT_EQ(harness.control_at("truck-1", at_ms(30))->returned_ack, second_pair);
  EXPECT_EQ(harness.control_at("truck-1", at_ms(40))->returned_ack, second_pair);
  EXPECT_EQ(harness.player.last_shared().vehicle_feedback.at("truck-1").ack, second_pair);
  EXPECT_EQ(harness.player.locked_source(), std::nullopt);
  EXPECT_EQ(harness.control_at("truck-1", at_ms(40))->client_user_data, std::nullopt);
}

TEST(Player, PluginSourceEchoesThePairItSent) {
  PlayerHarness harness;
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.start();
  harness.video_at(at_ms(1), "truck-1", second_pair);
  harness.client_data_at(at_ms(15), ClientSource::plugin, client_entry("truck-1", echo_entry(first_pair)));
  ClientVehicleEntry half;
  half.ack_time_returned = 5;  // mac missing: no pair at all
  harness.client_data_at(at_ms(25), ClientSource::plugin, client_entry("truck-1", half));
  harness.run_until(at_ms(30));
  EXPECT_EQ(harness.player.locked_source(), ClientSource::plugin);
  EXPECT_EQ(harness.control_at("truck-1", at_ms(10))->returned_ack, second_pair);  // self-echo
  EXPECT_EQ(harness.control_at("truck-1", at_ms(20))->returned_ack, first_pair);   // the plugin's
  EXPECT_EQ(harness.control_at("truck-1", at_ms(30))->returned_ack, std::nullopt);
}

TEST(Player, UserDataReachesTheVehicleLatestWins) {
  PlayerHarness harness;
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.start();
  harness.client_data_at(at_ms(5), ClientSource::plugin,
                         client_entry("truck-1", echo_entry(first_pair, R"({"n":1})")));
  harness.client_data_at(at_ms(15), ClientSource::plugin,
                         client_entry("truck-1", echo_entry(first_pair, R"({"n":2})")));
  harness.run_until(at_ms(30));
  EXPECT_EQ(harness.control_at("truck-1", at_ms(10))->client_user_data, RawJson{R"({"n":1})"});
  EXPECT_EQ(harness.control_at("truck-1", at_ms(20))->client_user_data, RawJson{R"({"n":2})"});
  EXPECT_EQ(harness.control_at("truck-1", at_ms(30))->client_user_data, RawJson{R"({"n":2})"});
}

TEST(Player, WebviewMessagesGetTheLatestPairInjected) {
  PlayerHarness harness;
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.start();
  harness.video_at(at_ms(2), "truck-1", first_pair);
  ClientVehicleEntry entry;
  entry.user_data = RawJson{R"({"from":"js"})"};
  harness.client_data_at(at_ms(5), ClientSource::webview, client_entry("truck-1", entry));
  harness.video_at(at_ms(12), "truck-1", second_pair);
  harness.client_data_at(at_ms(25), ClientSource::webview, client_entry("truck-1", entry));
  harness.run_until(at_ms(30));
  EXPECT_EQ(harness.player.locked_source(), ClientSource::webview);
  EXPECT_EQ(harness.control_at("truck-1", at_ms(10))->returned_ack, first_pair);
  // No web view message since the new pair arrived: the injected pair is still the old one.
  EXPECT_EQ(harness.control_at("truck-1", at_ms(20))->returned_ack, first_pair);
  EXPECT_EQ(harness.control_at("truck-1", at_ms(30))->returned_ack, second_pair);
  EXPECT_EQ(harness.control_at("truck-1", at_ms(30))->client_user_data, RawJson{R"({"from":"js"})"});
}

// SPEC §4.2 Decision (seeds 003, 004: the pair "is injected into every sendNamedUserMessage
// call"): a web view call with a bare entry is client data, not a keep-alive. It locks the
// source and each such call returns the latest pair; before issue #35 the bare entries were
// keep-alives and the loop stopped turning (HighLatency after about 400 ms).
TEST(Player, WebviewBareEntriesLockAndReturnTheLatestPair) {
  PlayerHarness harness;
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.start();
  harness.video_at(at_ms(2), "truck-1", first_pair);
  harness.client_data_at(at_ms(5), ClientSource::webview, client_entry("truck-1", ClientVehicleEntry{}));
  harness.video_at(at_ms(12), "truck-1", second_pair);
  harness.client_data_at(at_ms(15), ClientSource::webview, client_entry("truck-1", ClientVehicleEntry{}));
  harness.run_until(at_ms(20));
  EXPECT_EQ(harness.player.locked_source(), ClientSource::webview);
  EXPECT_EQ(harness.control_at("truck-1", at_ms(10))->returned_ack, first_pair);
  EXPECT_EQ(harness.control_at("truck-1", at_ms(20))->returned_ack, second_pair);
  EXPECT_EQ(harness.control_at("truck-1", at_ms(20))->client_user_data, std::nullopt);
}

// A web view call that names nothing ({}) returns no pair and locks nothing: self-echo goes on.
TEST(Player, WebviewCallNamingNothingLocksNothing) {
  PlayerHarness harness;
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.start();
  harness.video_at(at_ms(2), "truck-1", first_pair);
  harness.client_data_at(at_ms(5), ClientSource::webview, ClientOcpShared{});
  harness.run_until(at_ms(10));
  EXPECT_EQ(harness.player.locked_source(), std::nullopt);
  EXPECT_EQ(harness.control_at("truck-1", at_ms(10))->returned_ack, first_pair);   // self-echo
}

TEST(Player, SecondSourceStopsAllClientDataUntilRestart) {
  PlayerHarness harness;
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.start();
  harness.video_at(at_ms(1), "truck-1", first_pair);
  harness.client_data_at(at_ms(5), ClientSource::plugin,
                         client_entry("truck-1", echo_entry(first_pair, R"({"k":1})")));
  ClientVehicleEntry web;
  web.user_data = RawJson{R"({"k":2})"};
  harness.client_data_at(at_ms(15), ClientSource::webview, client_entry("truck-1", web));
  harness.video_at(at_ms(22), "truck-1", second_pair);
  harness.client_data_at(at_ms(35), ClientSource::plugin,
                         client_entry("truck-1", echo_entry(second_pair, R"({"k":3})")));
  harness.run_until(at_ms(40));

  const auto before = harness.control_at("truck-1", at_ms(10));
  ASSERT_TRUE(before.has_value());
  EXPECT_EQ(before->client_user_data, RawJson{R"({"k":1})"});
  EXPECT_EQ(before->returned_ack, first_pair);
  for (std::int64_t ms : {20, 30, 40}) {
    const auto after = harness.control_at("truck-1", at_ms(ms));
    ASSERT_TRUE(after.has_value()) << ms;
    EXPECT_EQ(after->client_user_data, std::nullopt) << ms;
    EXPECT_EQ(after->returned_ack, std::nullopt) << ms;  // no fallback to self-echo
  }
  EXPECT_TRUE(harness.player.client_data_stopped());
  EXPECT_EQ(harness.player.locked_source(), ClientSource::plugin);
  const CapturedLog::Line* error = harness.find_log(LogLevel::error, "conflict");
  ASSERT_NE(error, nullptr);
  EXPECT_NE(error->message.find("plugin"), std::string::npos);
  EXPECT_NE(error->message.find("webview"), std::string::npos);
  EXPECT_EQ(error->time, at_ms(15));
  EXPECT_EQ(harness.player.stats().source_conflicts, 1u);
  EXPECT_EQ(harness.player.stats().client_messages_ignored, 2u);
}

TEST(Player, ConflictKeepsGamepadDisabledAndSelection) {
  PlayerConfig config;
  config.fleet = true;
  PlayerHarness harness(config);
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  ASSERT_TRUE(harness.add_vehicle("truck-2").ok());
  harness.player.start();
  ClientVehicleEntry disabled;
  disabled.ocp_disable_gamepad = true;
  harness.client_data_at(at_ms(5), ClientSource::tcp, client_entry("truck-1", disabled, "truck-1"));
  ClientOcpShared other;
  other.active_vehicle = "truck-2";
  harness.client_data_at(at_ms(15), ClientSource::plugin, other);
  harness.run_until(at_ms(20));
  EXPECT_EQ(harness.player.active_vehicle(), "truck-1");
  EXPECT_EQ(harness.control_at("truck-1", at_ms(20))->controller, std::nullopt);
}

}  // namespace
}  // namespace ocp::testing
