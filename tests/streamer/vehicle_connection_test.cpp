// The vehicle connection lifecycle (SPEC §2, §3.1): one active connection, second refused,
// clean reconnect, read timeout, VehicleNoResponse.
#include "streamer_harness.hpp"

namespace ocp::streamer_test {
namespace {

TEST(StreamerVehicleConnection, SecondConnectionIsRefusedWhileTheFirstKeepsWorking) {
  StreamerHarness harness;
  TestVehicle& first = harness.connect_vehicle("pipe:vehicle-a");
  first.echo = true;
  harness.core.start();
  harness.executor.run_until(ms(100));
  TestVehicle& second = harness.connect_vehicle("pipe:vehicle-b");
  harness.executor.run_until(ms(200));

  EXPECT_TRUE(second.closed_by_peer());
  EXPECT_EQ(second.closed_at(), ms(100));
  EXPECT_TRUE(second.received.empty());
  EXPECT_TRUE(harness.logged("refused vehicle connection from pipe:vehicle-b: pipe:vehicle-a is already connected"));
  EXPECT_EQ(harness.core.stats().connections_refused, 1u);
  EXPECT_EQ(harness.core.stats().connections_accepted, 1u);
  EXPECT_FALSE(first.closed_by_peer());
  EXPECT_EQ(first.received.size(), 21u);
  EXPECT_EQ(harness.core.vehicle_peer(), "pipe:vehicle-a");
}

// Issue #19 item 8: a Streamer stopped (SIGSTOP) and resumed meets the vehicle client's new
// connection before it has read the old one's close, and said "refused … already connected"
// for a peer that had hung up. A peer that has hung up is not connected: the newcomer is taken.
TEST(StreamerVehicleConnection, APeerThatHungUpDoesNotKeepTheNextOneOut) {
  StreamerHarness harness;
  TestVehicle& first = harness.connect_vehicle("pipe:vehicle-a");
  first.echo = true;
  harness.core.start();
  harness.executor.run_until(ms(100));
  first.close();                                            // its close is not read yet …
  TestVehicle& second = harness.connect_vehicle("pipe:vehicle-b");   // … when this one comes
  second.echo = true;
  harness.executor.run_until(ms(200));

  EXPECT_FALSE(harness.logged("refused"));
  EXPECT_EQ(harness.core.stats().connections_refused, 0u);
  EXPECT_EQ(harness.core.stats().connections_accepted, 2u);
  EXPECT_EQ(harness.core.stats().connections_closed, 1u);
  EXPECT_EQ(harness.core.stats().last_close_reason,
            (CloseReason{PeerError::closed_by_peer, "it had hung up already when pipe:vehicle-b connected"}));
  EXPECT_FALSE(second.closed_by_peer());
  EXPECT_TRUE(harness.core.vehicle_connected());
  EXPECT_EQ(harness.core.vehicle_peer(), "pipe:vehicle-b");
  EXPECT_EQ(second.received.size(), 10u);   // ticks at 110 … 200 ms
}

TEST(StreamerVehicleConnection, ReconnectStartsCleanWithoutStaleControlMessages) {
  StreamerHarness harness;
  TestVehicle& first = harness.connect_vehicle("pipe:vehicle-a");
  first.echo = true;
  harness.core.start();
  harness.executor.run_until(ms(100));
  first.close();
  harness.executor.run_until(ms(155));
  EXPECT_FALSE(harness.core.vehicle_connected());
  TestVehicle& second = harness.connect_vehicle("pipe:vehicle-b");
  harness.executor.run_until(ms(300));

  ASSERT_FALSE(second.received.empty());
  // The first frame the new vehicle sees is built at the first tick after it connected.
  EXPECT_EQ(second.received_at.front(), ms(160));
  EXPECT_EQ(second.received.front().ack.ack_time, 160'000u);
  for (const auto& message : second.received) EXPECT_GE(message.ack.ack_time, 160'000u);
  EXPECT_EQ(second.received.size(), 15u);
  EXPECT_EQ(harness.core.stats().connections_accepted, 2u);
  EXPECT_EQ(harness.core.stats().connections_closed, 1u);
  EXPECT_EQ(harness.observer.changes(FaultId::VehicleNoResponse, true),
            std::vector<SimTime>{ms(100)});
  EXPECT_EQ(harness.observer.changes(FaultId::VehicleNoResponse, false),
            std::vector<SimTime>{ms(155)});
  EXPECT_EQ(harness.core.stats().last_close_reason, (CloseReason{PeerError::closed_by_peer, "closed by peer"}));
}

TEST(StreamerVehicleConnection, VehicleNoResponseExactlyWhileNoVehicleIsConnected) {
  StreamerHarness harness;
  harness.core.start();
  EXPECT_TRUE(harness.core.faults().contains(FaultId::VehicleNoResponse));
  harness.executor.run_until(ms(50));
  TestVehicle& vehicle = harness.connect_vehicle();
  vehicle.echo = true;
  EXPECT_FALSE(harness.core.faults().contains(FaultId::VehicleNoResponse));
  harness.executor.run_until(ms(80));
  vehicle.close();
  harness.executor.run_until(ms(80));
  EXPECT_TRUE(harness.core.faults().contains(FaultId::VehicleNoResponse));
  EXPECT_EQ(harness.observer.connections.size(), 2u);
  EXPECT_TRUE(harness.observer.connections[0].first);
  EXPECT_FALSE(harness.observer.connections[1].first);
  EXPECT_EQ(harness.observer.changes(FaultId::VehicleNoResponse, true),
            (std::vector<SimTime>{ms(0), ms(80)}));
}

TEST(StreamerVehicleConnection, ClosesAfter2000MsWithoutAnyByte) {
  StreamerHarness harness;
  TestVehicle& vehicle = harness.connect_vehicle();
  harness.core.start();
  harness.executor.run_until(ms(1999));
  EXPECT_FALSE(vehicle.closed_by_peer());
  harness.executor.run_until(ms(2000));
  EXPECT_TRUE(vehicle.closed_by_peer());
  EXPECT_EQ(vehicle.closed_at(), ms(2000));
  EXPECT_EQ(harness.core.stats().last_close_reason,
            (CloseReason{PeerError::read_timeout, "no data from the vehicle for 2000 ms"}));
  EXPECT_TRUE(harness.logged("read timeout"));
  EXPECT_TRUE(harness.core.faults().contains(FaultId::VehicleNoResponse));
}

TEST(StreamerVehicleConnection, ReadTimeoutRunsBetweenFramesAndInsideOne) {
  StreamerHarness harness;
  TestVehicle& vehicle = harness.connect_vehicle();
  harness.core.start();
  harness.executor.run_until(ms(700));
  vehicle.send_response(VehicleResponseMessage{AckPair{1, 1}, std::nullopt});
  harness.executor.run_until(ms(1500));
  vehicle.send_raw(std::string(2, '\x10'));  // half a frame header, then silence
  harness.executor.run_until(ms(3499));
  EXPECT_FALSE(vehicle.closed_by_peer());
  harness.executor.run_until(ms(3500));
  EXPECT_TRUE(vehicle.closed_by_peer());
  EXPECT_EQ(vehicle.closed_at(), ms(3500));
}

TEST(StreamerVehicleConnection, EchoingVehicleIsNeverTimedOut) {
  StreamerHarness harness;
  TestVehicle& vehicle = harness.connect_vehicle();
  vehicle.echo = true;
  harness.core.start();
  harness.executor.run_until(ms(10'000));
  EXPECT_FALSE(vehicle.closed_by_peer());
  EXPECT_EQ(harness.core.stats().vehicle_responses_received, 1001u);
  EXPECT_EQ(harness.core.stats().control_frames_sent, 1001u);
  std::uint64_t framed_bytes = 0;
  for (const auto& payload : vehicle.raw_payloads) framed_bytes += payload.size() + frame_header_bytes;
  EXPECT_EQ(harness.core.stats().vehicle_bytes_out, framed_bytes);
  EXPECT_GT(harness.core.stats().vehicle_bytes_in, 1001u * frame_header_bytes);
}

TEST(StreamerVehicleConnection, StopClosesTheConnection) {
  StreamerHarness harness;
  TestVehicle& vehicle = harness.connect_vehicle();
  harness.core.start();
  harness.executor.run_until(ms(30));
  harness.core.stop();
  harness.executor.run_until(ms(100));
  EXPECT_TRUE(vehicle.closed_by_peer());
  EXPECT_EQ(vehicle.received.size(), 4u);
  EXPECT_EQ(harness.core.stats().last_close_reason, (CloseReason{LocalError::shut_down, "streamer stopped"}));
}

}  // namespace
}  // namespace ocp::streamer_test
