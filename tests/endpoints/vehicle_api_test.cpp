// The Streamer's vehicle API (:4000) on real loopback sockets, driven in real time by
// StreamerSimulation (the streamer_sim executable's world). Ports are ephemeral; every wait is
// on a condition with a generous bound.
#include <gtest/gtest.h>

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <memory>

#include "endpoint_fixture.hpp"
#include "streamer_app/streamer_simulation.hpp"

namespace ocp {
namespace {

using testing::CapturedLog;
using testing::EchoingVehicle;
using TcpClient = testing::TcpTestClient<>;
using testing::run_until;

class VehicleApi : public ::testing::Test {
 protected:
  void SetUp() override {
    StreamerSimOptions options;
    options.plugin_params.tcp_port = 0;
    simulation_ = std::make_unique<StreamerSimulation>(executor_, options, log_.sink());
    ASSERT_TRUE(simulation_->start().ok());
    started_at_ = executor_.now();
    ASSERT_NE(simulation_->port(), 0);
  }
  void TearDown() override { simulation_.reset(); }

  StreamerCore& streamer() { return simulation_->streamer(); }
  std::uint16_t port() const { return simulation_->port(); }

  boost::asio::io_context io_;
  AsioExecutor executor_{io_};
  CapturedLog log_;
  std::unique_ptr<StreamerSimulation> simulation_;
  SimTime started_at_{};
};

TEST_F(VehicleApi, ControlMessagesArriveEvery10msAndTheEchoClosesTheLatencyLoop) {
  EchoingVehicle vehicle(io_);
  ASSERT_TRUE(vehicle.connect(port()));
  ASSERT_TRUE(run_until(io_, [&] { return vehicle.received.size() >= 1; }));
  const auto first_at = std::chrono::steady_clock::now();
  ASSERT_TRUE(run_until(io_, [&] { return vehicle.received.size() >= 101; }));
  const auto hundred_ticks = std::chrono::steady_clock::now() - first_at;
  // Absolute 10 ms deadlines: 100 more messages cannot come faster than ~1 s; a loaded
  // machine may skip ticks, so only a generous upper bound.
  EXPECT_GE(hundred_ticks, std::chrono::milliseconds(950));
  EXPECT_LE(hundred_ticks, std::chrono::milliseconds(5000));

  // The echo closes the loop: InvalidMac clears and the latency is measured.
  ASSERT_TRUE(run_until(io_, [&] {
    return !streamer().faults().contains(FaultId::InvalidMac) && streamer().latency_ms().has_value() &&
           streamer().faults().empty();
  }));
  // …and the vehicle sees it in telemetry.
  ASSERT_TRUE(run_until(io_, [&] { return !vehicle.received.back().telemetry.fault; }));
  EXPECT_EQ(vehicle.received.back().telemetry.fault_reason, "");
  EXPECT_EQ(vehicle.undecodable, 0u);
  // Every control message carries a fresh pair.
  const auto& messages = vehicle.received;
  for (std::size_t i = 1; i < messages.size(); ++i) {
    EXPECT_GT(messages[i].ack.ack_time, messages[i - 1].ack.ack_time);
  }
}

TEST_F(VehicleApi, SecondClientIsRefusedWhileTheFirstKeepsWorking) {
  EchoingVehicle first(io_);
  ASSERT_TRUE(first.connect(port()));
  ASSERT_TRUE(run_until(io_, [&] { return streamer().vehicle_connected(); }));

  TcpClient second(io_);
  ASSERT_TRUE(second.connect(port()));
  ASSERT_TRUE(run_until(io_, [&] { return second.closed_by_peer(); }));
  EXPECT_EQ(second.frames().size(), 0u);
  EXPECT_EQ(streamer().stats().connections_refused, 1u);
  // The log line names both peers.
  EXPECT_TRUE(log_.contains("refused vehicle connection from 127.0.0.1:"));
  EXPECT_TRUE(log_.contains("is already connected"));

  const std::size_t before = first.received.size();
  ASSERT_TRUE(run_until(io_, [&] { return first.received.size() >= before + 20; }));
  EXPECT_TRUE(first.is_open());
  EXPECT_TRUE(streamer().vehicle_connected());
}

TEST_F(VehicleApi, TwoSecondsOfSilenceCloseTheConnection) {
  TcpClient silent(io_);
  ASSERT_TRUE(silent.connect(port()));
  ASSERT_TRUE(run_until(io_, [&] { return streamer().vehicle_connected(); }));
  const auto connected_at = std::chrono::steady_clock::now();
  ASSERT_TRUE(run_until(io_, [&] { return silent.closed_by_peer(); }));
  const auto silence = std::chrono::steady_clock::now() - connected_at;
  EXPECT_GE(silence, std::chrono::milliseconds(1900));
  EXPECT_LE(silence, std::chrono::milliseconds(6000));
  EXPECT_GT(silent.frames().size(), 50u);   // it was sent control messages all along
  ASSERT_TRUE(streamer().stats().last_close_reason.has_value());
  EXPECT_EQ(streamer().stats().last_close_reason->code, PeerError::read_timeout);
  EXPECT_TRUE(streamer().faults().contains(FaultId::VehicleNoResponse));
}

TEST_F(VehicleApi, OversizedFrameIsSkippedAndTheConnectionSurvives) {
  EchoingVehicle vehicle(io_);
  ASSERT_TRUE(vehicle.connect(port()));
  ASSERT_TRUE(run_until(io_, [&] { return vehicle.received.size() >= 5; }));

  constexpr std::uint32_t oversized_bytes = 16'385;
  vehicle.send_payload(std::string(oversized_bytes, '{'));  // not even JSON: it must never be parsed

  ASSERT_TRUE(run_until(io_, [&] { return streamer().stats().oversized_frames_dropped == 1; }));
  const std::uint64_t responses = streamer().stats().vehicle_responses_received;
  ASSERT_TRUE(run_until(io_, [&] { return streamer().stats().vehicle_responses_received >= responses + 20; }));
  EXPECT_TRUE(vehicle.is_open());
  EXPECT_EQ(streamer().stats().connections_closed, 0u);
  EXPECT_TRUE(log_.contains("dropped oversized frame of 16385 bytes"));
}

TEST_F(VehicleApi, MalformedJsonClosesTheConnectionWithTheReasonLogged) {
  TcpClient vehicle(io_);
  ASSERT_TRUE(vehicle.connect(port()));
  ASSERT_TRUE(run_until(io_, [&] { return streamer().vehicle_connected(); }));
  vehicle.send_payload(R"({"ack_time": 12, "ack_time_mac": )");
  ASSERT_TRUE(run_until(io_, [&] { return vehicle.closed_by_peer(); }));
  EXPECT_FALSE(streamer().vehicle_connected());
  EXPECT_EQ(streamer().stats().connections_closed, 1u);
  ASSERT_TRUE(streamer().stats().last_close_reason.has_value());
  EXPECT_EQ(streamer().stats().last_close_reason->code, PeerError::malformed_json);
  EXPECT_TRUE(log_.contains("closing vehicle connection 127.0.0.1:"));
}

TEST_F(VehicleApi, MissingRequiredFieldClosesTheConnection) {
  TcpClient vehicle(io_);
  ASSERT_TRUE(vehicle.connect(port()));
  vehicle.send_payload(R"({"ack_time": 12})");
  ASSERT_TRUE(run_until(io_, [&] { return vehicle.closed_by_peer(); }));
  ASSERT_TRUE(streamer().stats().last_close_reason.has_value());
  EXPECT_EQ(streamer().stats().last_close_reason->code, PeerError::missing_field);
  EXPECT_NE(streamer().stats().last_close_reason->detail.find("ack_time_mac"), std::string::npos)
      << streamer().stats().last_close_reason->message();
}

TEST_F(VehicleApi, ReconnectGetsFreshMessagesAndNoStaleQueuedOnes) {
  {
    EchoingVehicle first(io_);
    ASSERT_TRUE(first.connect(port()));
    ASSERT_TRUE(run_until(io_, [&] { return first.received.size() >= 10; }));
    first.close();
    ASSERT_TRUE(run_until(io_, [&] { return !streamer().vehicle_connected(); }));
  }
  // Control ticks keep running with nobody connected; none of them may be delivered later.
  testing::run_for(io_, std::chrono::milliseconds(200));

  const SimTime reconnect_at = executor_.now();
  EchoingVehicle second(io_);
  ASSERT_TRUE(second.connect(port()));
  ASSERT_TRUE(run_until(io_, [&] { return second.received.size() >= 10; }));
  // ack_time = µs since the Streamer started (offset 0), and the Streamer started before
  // started_at_: every pair the new connection sees was issued after it connected.
  const auto issued_after = static_cast<std::uint64_t>((reconnect_at - started_at_).count());
  for (const auto& message : second.received) EXPECT_GE(message.ack.ack_time, issued_after);
  EXPECT_EQ(streamer().stats().connections_accepted, 2u);
}

TEST_F(VehicleApi, PortInUseIsAClearError) {
  StreamerSimOptions options;
  options.plugin_params.tcp_port = port();
  StreamerSimulation second(executor_, options, {});
  const Status status = second.start();
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().code, std::errc::address_in_use);
  EXPECT_EQ(status.error().detail.rfind("another socket listens on 127.0.0.1:" + std::to_string(port()) + " (", 0), 0u)
      << status.error().detail;
  EXPECT_FALSE(second.world().running());
  // The first one is unaffected.
  EchoingVehicle vehicle(io_);
  ASSERT_TRUE(vehicle.connect(port()));
  ASSERT_TRUE(run_until(io_, [&] { return vehicle.received.size() >= 3; }));
}

}  // namespace
}  // namespace ocp
