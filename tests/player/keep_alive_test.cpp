// A read-only operator client (a dashboard) and its keep-alive (SPEC §4.2, §4.3): a
// ClientOcpShared without client data resets the :4001 read timer and locks nothing, so the
// Player keeps echoing the SEI pair itself. And a client naming an unknown active_vehicle in
// every message is warned about once per episode, not 100 times a second.
#include <gtest/gtest.h>

#include <algorithm>

#include "player_harness.hpp"

namespace ocp::testing {
namespace {

constexpr AckPair sei_pair{9'007'199'254'740'993ULL, 4'000'000'001U};

class Dashboard : public ::testing::Test {
 protected:
  Dashboard() {
    EXPECT_TRUE(harness.add_vehicle("truck-1").ok());
    harness.player.start();
  }
  PlayerHarness harness;
};

TEST(KeepAlive, OnlyMessagesWithoutClientDataAreKeepAlives) {
  EXPECT_TRUE(is_keep_alive(ClientOcpShared{}));
  EXPECT_TRUE(is_keep_alive(client_entry("truck-1", ClientVehicleEntry{})));  // an empty entry
  ClientOcpShared active;
  active.active_vehicle = "truck-1";
  EXPECT_FALSE(is_keep_alive(active));
  ClientVehicleEntry gamepad_off;
  gamepad_off.ocp_disable_gamepad = false;  // any field, whatever its value
  EXPECT_FALSE(is_keep_alive(client_entry("truck-1", gamepad_off)));
  ClientVehicleEntry user_data;
  user_data.user_data = RawJson{"null"};
  EXPECT_FALSE(is_keep_alive(client_entry("no-such-truck", user_data)));
  // The tcp client and plugins fill the pair themselves: a bare entry is a keep-alive for them,
  // never for the web view, whose pair the Player injects (SPEC §4.2 Decision).
  EXPECT_TRUE(is_keep_alive(ClientSource::tcp, client_entry("truck-1", ClientVehicleEntry{})));
  EXPECT_TRUE(is_keep_alive(ClientSource::plugin, client_entry("truck-1", ClientVehicleEntry{})));
  EXPECT_FALSE(is_keep_alive(ClientSource::webview, client_entry("truck-1", ClientVehicleEntry{})));
  EXPECT_TRUE(is_keep_alive(ClientSource::webview, ClientOcpShared{}));
  EXPECT_FALSE(is_keep_alive(ClientSource::webview, active));
}

TEST_F(Dashboard, KeepAliveEverySecondForTenSecondsKeepsTheClientAndTheSelfEcho) {
  TestOperatorClient client(harness);
  harness.video_at(at_ms(5), "truck-1", sei_pair);
  for (int second = 1; second <= 10; ++second) {
    harness.executor.call_at(at_ms(1000 * second), [&] { client.send(ClientOcpShared{}); });
  }
  harness.run_until(at_ms(10'500));
  EXPECT_FALSE(client.closed_by_peer()) << client.close_reason();
  EXPECT_EQ(harness.player.locked_source(), std::nullopt);
  EXPECT_EQ(harness.player.stats().client_keep_alives, 10u);
  // Self-echo in every frame of the run, so the Streamer never loses its loop.
  const auto controls = harness.controls("truck-1");
  ASSERT_FALSE(controls.empty());
  for (const auto& [time, control] : controls) {
    if (time > at_ms(10)) {
      ASSERT_EQ(control.returned_ack, sei_pair) << "at " << time.count() << " us";
    }
  }
}

TEST_F(Dashboard, ReadTimeoutCountsFromTheLastKeepAlive) {
  TestOperatorClient client(harness);
  harness.executor.call_at(at_ms(1500), [&] { client.send(ClientOcpShared{}); });
  harness.run_until(SimTime{3'499'999});
  EXPECT_FALSE(client.closed_by_peer());
  harness.run_until(SimTime{3'500'000});
  EXPECT_TRUE(client.closed_by_peer());
  EXPECT_EQ(client.closed_at(), SimTime{3'500'000});
}

TEST_F(Dashboard, KeepAlivesDoNotConflictWithTheLockedSource) {
  // The plugin holds the lock; a dashboard on :4001 that only keeps alive must not stop it.
  ClientVehicleEntry echo;
  echo.ack_time_returned = sei_pair.ack_time;
  echo.ack_time_mac_returned = sei_pair.ack_time_mac;
  harness.client_data_at(at_ms(5), ClientSource::plugin, client_entry("truck-1", echo));
  TestOperatorClient client(harness);
  harness.executor.call_at(at_ms(500), [&] { client.send(ClientOcpShared{}); });
  harness.run_until(at_ms(600));
  EXPECT_EQ(harness.player.locked_source(), ClientSource::plugin);
  EXPECT_FALSE(harness.player.client_data_stopped());
  EXPECT_EQ(harness.control_at("truck-1", at_ms(590))->returned_ack, sei_pair);
}

TEST_F(Dashboard, RealClientDataAfterKeepAlivesStillLocks) {
  TestOperatorClient client(harness);
  harness.executor.call_at(at_ms(100), [&] { client.send(ClientOcpShared{}); });
  ClientOcpShared select;
  select.active_vehicle = "truck-1";
  harness.executor.call_at(at_ms(200), [&] { client.send(select); });
  harness.run_until(at_ms(150));
  EXPECT_EQ(harness.player.locked_source(), std::nullopt);
  harness.run_until(at_ms(250));
  EXPECT_EQ(harness.player.locked_source(), ClientSource::tcp);
}

std::size_t count_logs(const PlayerHarness& harness, const std::string& needle) {
  const auto& lines = harness.log.lines();
  return static_cast<std::size_t>(std::count_if(lines.begin(), lines.end(), [&](const CapturedLog::Line& line) {
    return line.message.find(needle) != std::string::npos;
  }));
}

TEST_F(Dashboard, UnknownActiveVehicleIsWarnedOncePerEpisode) {
  ClientOcpShared unknown;
  unknown.active_vehicle = "truck-9";
  ClientOcpShared known;
  known.active_vehicle = "truck-1";
  for (int ms = 0; ms < 1000; ms += 10) harness.client_data_at(at_ms(ms), ClientSource::plugin, unknown);
  harness.run_until(at_ms(1000));
  EXPECT_EQ(count_logs(harness, "active_vehicle 'truck-9'"), 1u);
  // A valid selection ends the episode; naming the unknown vehicle again starts a new one.
  harness.client_data_at(at_ms(1000), ClientSource::plugin, known);
  for (int ms = 1010; ms < 1100; ms += 10) harness.client_data_at(at_ms(ms), ClientSource::plugin, unknown);
  harness.run_until(at_ms(1100));
  EXPECT_EQ(count_logs(harness, "active_vehicle 'truck-9'"), 2u);
}

}  // namespace
}  // namespace ocp::testing
