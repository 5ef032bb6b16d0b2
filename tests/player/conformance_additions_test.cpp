// The PlayerCore additions the `ocp_conformance operator` suite uses (player_core.hpp,
// "Conformance testing"), in virtual time over a pipe: paused client output, server close.
#include <gtest/gtest.h>

#include "player_harness.hpp"

namespace ocp::testing {
namespace {

class PlayerConformanceAdditions : public ::testing::Test {
 protected:
  PlayerConformanceAdditions() {
    EXPECT_TRUE(harness.add_vehicle("truck-1").ok());
    harness.player.start();
  }
  PlayerHarness harness;
};

TEST_F(PlayerConformanceAdditions, PausedClientOutputWritesNothingButFramesGoOn) {
  TestOperatorClient client(harness);
  harness.run_until(at_ms(100));
  const std::size_t before = client.received.size();
  EXPECT_GE(before, 9u);
  harness.player.set_client_output_paused(true);
  EXPECT_TRUE(harness.player.client_output_paused());
  const std::size_t controls = harness.controls("truck-1").size();
  harness.run_until(at_ms(600));
  EXPECT_EQ(client.received.size(), before);
  EXPECT_GE(harness.controls("truck-1").size(), controls + 49);   // the vehicle still gets control
  harness.player.set_client_output_paused(false);
  harness.run_until(at_ms(650));
  EXPECT_GT(client.received.size(), before);
}

TEST_F(PlayerConformanceAdditions, PausedOutputLetsTheReadTimeoutFireOnASilentClient) {
  TestOperatorClient client(harness);
  harness.player.set_client_output_paused(true);
  harness.run_until(at_ms(2'100));
  EXPECT_TRUE(client.closed_by_peer());
  ASSERT_TRUE(harness.player.last_client_close_reason().has_value());
  EXPECT_EQ(harness.player.last_client_close_reason()->code, PeerError::read_timeout);
}

TEST_F(PlayerConformanceAdditions, CloseClientConnectionClosesFromTheServerSide) {
  TestOperatorClient client(harness);
  harness.run_until(at_ms(50));
  ASSERT_TRUE(harness.player.client_connected());
  harness.player.close_client_connection();
  harness.run_until(at_ms(60));
  EXPECT_FALSE(harness.player.client_connected());
  EXPECT_TRUE(client.closed_by_peer());
  ASSERT_TRUE(harness.player.last_client_close_reason().has_value());
  EXPECT_EQ(harness.player.last_client_close_reason()->code, LocalError::shut_down);
  harness.player.close_client_connection();   // no client: no-op
  // The next client is accepted (nothing left of the closed one).
  TestOperatorClient next(harness, "pipe:operator-2");
  harness.run_until(at_ms(100));
  EXPECT_TRUE(harness.player.client_connected());
  EXPECT_FALSE(next.received.empty());
}

}  // namespace
}  // namespace ocp::testing
