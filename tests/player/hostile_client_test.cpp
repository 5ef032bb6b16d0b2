// Issue #19, virtual time: what a client can make the Player remember or log is bounded.
//  * item 2: a client sending ever-new unknown vehicle names grew RSS from 10 MB to 197 MB in
//    10 s and wrote 2.39 M warnings (one set entry and one line per name).
//  * item 7: from 17 vehicles up VehicleOcpShared is over 16 KiB and never sent to the :4001
//    client; the Player says so where the user looks, with what to reduce.
//  * a client that hung up does not keep a newcomer out before its close is read.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "ocp/frame.hpp"
#include "ocp/log_limiter.hpp"
#include "player_harness.hpp"

namespace ocp::testing {
namespace {

std::size_t lines_containing(const PlayerHarness& harness, const std::string& needle) {
  const auto& lines = harness.log.lines();
  return static_cast<std::size_t>(std::count_if(lines.begin(), lines.end(), [&](const CapturedLog::Line& line) {
    return line.message.find(needle) != std::string::npos;
  }));
}

TEST(PlayerHostileClient, EverNewUnknownVehicleNamesAreRememberedAndLoggedBoundedly) {
  PlayerHarness harness;
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.start();
  // 100 000 messages in 10 s, each naming a new vehicle (and selecting one) that is not linked.
  constexpr int messages = 100'000;
  for (int k = 0; k < messages; ++k) {
    harness.executor.run_until(SimTime{k * 100});
    ClientVehicleEntry entry;
    entry.user_data = RawJson{"1"};
    harness.player.handle_client_data(ClientSource::plugin,
                                      client_entry("ghost-" + std::to_string(k), entry, "ghost-" + std::to_string(k)));
    // Also a Streamer link naming a vehicle the Player does not have.
    harness.player.handle_link_message("stranger-" + std::to_string(k), LinkMessage{Pong{0, SimTime{0}}});
    ASSERT_LE(harness.player.remembered_unknown_names(), 3 * WarnedNames::default_capacity);
  }
  harness.run_until(at_ms(20'000));
  EXPECT_EQ(harness.player.stats().unknown_vehicle_entries, static_cast<std::uint64_t>(messages));
  EXPECT_EQ(harness.player.remembered_unknown_names(), 3 * WarnedNames::default_capacity);

  // 64 names in full per kind, then one count every 5 s: a few lines, not 300 000.
  const std::size_t entry_lines = lines_containing(harness, "client_user_data for unknown vehicle");
  const std::size_t entry_summaries = lines_containing(harness, "more client_user_data entries for unknown vehicle names");
  EXPECT_EQ(entry_lines, WarnedNames::default_capacity);
  EXPECT_GE(entry_summaries, 2u);
  EXPECT_LE(entry_summaries, 3u);
  EXPECT_TRUE(harness.logged(LogLevel::warn, "further unknown names are only counted, every 5 s"));
  EXPECT_LE(lines_containing(harness, "active_vehicle 'ghost-"), WarnedNames::default_capacity);
  EXPECT_LE(lines_containing(harness, "message from unknown vehicle"), WarnedNames::default_capacity);
  EXPECT_LE(harness.log.lines().size(), 3 * WarnedNames::default_capacity + 20);
  const CapturedLog::Line* first_count = harness.find_log(LogLevel::warn, "more client_user_data entries");
  ASSERT_NE(first_count, nullptr);
  EXPECT_NE(first_count->message.find(" in the last 5 s"), std::string::npos) << first_count->message;
}

PlayerConfig fleet_config() {
  PlayerConfig config;
  config.fleet = true;
  config.client_read_timeout = Micros{0};   // the test's client never writes
  return config;
}

// 20 vehicles, each reporting ~1 KB of vehicle data: VehicleOcpShared is over 16 KiB.
TEST(PlayerHostileClient, ATooLargeVehicleOcpSharedIsShownWhileItLasts) {
  PlayerHarness harness(fleet_config());
  for (int k = 0; k < 20; ++k) ASSERT_TRUE(harness.add_vehicle("vehicle-" + std::to_string(k)).ok());
  harness.player.start();
  StreamerFeedback feedback;
  feedback.vehicle_data = VehicleUserData{Position{57.7, 11.9}, RawJson{"\"" + std::string(1000, 'd') + "\""}};
  feedback.last_remote_input = Controller::safe_default();
  for (std::int64_t ms = 0; ms < 1000; ms += 100) {
    for (const std::string& vehicle : harness.player.vehicles()) {
      harness.deliver_at(at_ms(ms), vehicle, LinkMessage{feedback});
    }
  }
  PipeEnds pipe = make_pipe(harness.executor);
  pipe.b->set_handlers({[](std::string_view) {}, [](const std::string&) {}});
  harness.player.accept_client_connection(pipe.a);
  harness.run_until(at_ms(1000));

  ASSERT_GT(harness.player.stats().client_frames_too_large, 0u);
  const auto& too_large = harness.player.client_frame_too_large();
  ASSERT_TRUE(too_large.has_value());
  EXPECT_GT(too_large->bytes, max_payload_bytes);
  EXPECT_EQ(too_large->limit, max_payload_bytes);
  EXPECT_EQ(too_large->vehicles, 20u);
  EXPECT_EQ(too_large->frames, harness.player.stats().client_frames_too_large);
  EXPECT_EQ(describe(*too_large), "VehicleOcpShared too large: " + std::to_string(too_large->bytes) +
                                      " B > 16384 B, not sent to the client (" + std::to_string(too_large->frames) +
                                      " frames)");
  // One warning, with the size, the limit and what to reduce.
  ASSERT_EQ(lines_containing(harness, "VehicleOcpShared not sent"), 1u);
  const CapturedLog::Line* warning = harness.find_log(LogLevel::warn, "VehicleOcpShared not sent");
  ASSERT_NE(warning, nullptr);
  EXPECT_NE(warning->message.find("over the 16384-byte frame limit"), std::string::npos) << warning->message;
  EXPECT_NE(warning->message.find("fewer vehicles (20 linked), smaller vehicle_user_data, fewer cameras"),
            std::string::npos)
      << warning->message;

  // Without a client nothing is being withheld.
  pipe.b->close();
  harness.run_until(at_ms(1100));
  EXPECT_FALSE(harness.player.client_connected());
  EXPECT_FALSE(harness.player.client_frame_too_large().has_value());
}

// A client that has hung up, its close not read yet, does not keep a new client out.
TEST(PlayerHostileClient, AClientThatHungUpDoesNotKeepTheNextOneOut) {
  PlayerHarness harness;
  ASSERT_TRUE(harness.add_vehicle("truck-1").ok());
  harness.player.start();
  PipeOptions old_options;
  old_options.name_b = "pipe:old-client";
  PipeEnds old_pipe = make_pipe(harness.executor, old_options);
  old_pipe.b->set_handlers({[](std::string_view) {}, [](const std::string&) {}});
  harness.player.accept_client_connection(old_pipe.a);
  harness.run_until(at_ms(100));
  ASSERT_TRUE(harness.player.client_connected());

  old_pipe.b->close();   // the old client leaves; the Player has not read that yet …
  PipeOptions new_options;
  new_options.name_b = "pipe:new-client";
  PipeEnds new_pipe = make_pipe(harness.executor, new_options);
  std::size_t received = 0;
  new_pipe.b->set_handlers({[&](std::string_view bytes) { received += bytes.size(); }, [](const std::string&) {}});
  harness.player.accept_client_connection(new_pipe.a);   // … when the new one arrives
  harness.run_until(at_ms(200));

  EXPECT_EQ(harness.player.stats().client_connections_refused, 0u);
  EXPECT_FALSE(harness.logged(LogLevel::warn, "refused"));
  EXPECT_TRUE(harness.player.client_connected());
  EXPECT_GT(received, 0u);
}

}  // namespace
}  // namespace ocp::testing
