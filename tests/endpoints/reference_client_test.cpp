// The reference vehicle client (VehicleClient + TcpRunner, the code of the `vehicle_client`
// executable) over real loopback TCP against the Streamer front of streamer_sim.
#include <gtest/gtest.h>

#include <boost/asio/io_context.hpp>
#include <memory>

#include "endpoint_fixture.hpp"
#include "streamer_app/streamer_simulation.hpp"
#include "vehicle_app/tcp_runner.hpp"

namespace ocp {
namespace {

using testing::CapturedLog;
using testing::run_until;

class ReferenceClientOverTcp : public ::testing::Test {
 protected:
  void start_streamer(std::uint16_t port) {
    StreamerSimOptions options;
    options.plugin_params.tcp_port = port;
    simulation_ = std::make_unique<StreamerSimulation>(executor_, options, log_.sink());
    ASSERT_TRUE(simulation_->start().ok());
  }
  void start_vehicle() {
    client_ = std::make_unique<VehicleClient>(executor_, VehicleClientConfig{},
                                              Logger(executor_, "vehicle-client", log_.sink()));
    TcpRunnerConfig config;
    config.server.port = simulation_->port();
    runner_ = std::make_unique<TcpRunner>(executor_, *client_, config,
                                          Logger(executor_, "vehicle-client:tcp", log_.sink()));
    runner_->start();
  }
  void TearDown() override {
    if (runner_) runner_->stop();
    runner_.reset();
    client_.reset();
    simulation_.reset();
  }
  bool loop_closed() {
    StreamerCore& streamer = simulation_->streamer();
    return streamer.vehicle_connected() && streamer.faults().empty() && streamer.latency_ms().has_value();
  }

  boost::asio::io_context io_;
  AsioExecutor executor_{io_};
  CapturedLog log_;
  std::unique_ptr<StreamerSimulation> simulation_;
  std::unique_ptr<VehicleClient> client_;
  std::unique_ptr<TcpRunner> runner_;
};

TEST_F(ReferenceClientOverTcp, LatencyLoopClosesAndEveryFaultClears) {
  start_streamer(0);
  start_vehicle();
  ASSERT_TRUE(run_until(io_, [&] { return loop_closed(); }));
  // The link of the simulated operator has no delay here, so the loop is short.
  EXPECT_LT(*simulation_->streamer().latency_ms(), 500u);
  EXPECT_GT(client_->stats().echo_responses_sent, 0u);
  EXPECT_TRUE(run_until(io_, [&] { return !client_->stats().last_telemetry_fault; }));
}

TEST_F(ReferenceClientOverTcp, VehicleUserDataReachesTheOperatorSide) {
  start_streamer(0);
  start_vehicle();
  ASSERT_TRUE(run_until(io_, [&] {
    const auto& feedback = simulation_->player().last_shared().vehicle_feedback;
    const auto found = feedback.find("vehicle");
    return found != feedback.end() && found->second.vehicle_data.has_value() &&
           found->second.vehicle_data->pos.has_value();
  }));
  const auto& data = *simulation_->player().last_shared().vehicle_feedback.at("vehicle").vehicle_data;
  EXPECT_NE(data.user_data.text.find("speed_mps"), std::string::npos) << data.user_data.text;
  EXPECT_NEAR(data.pos->lat, client_->config().start.lat, 0.01);
}

TEST_F(ReferenceClientOverTcp, ReconnectsAfterTheStreamerRestarts) {
  start_streamer(0);
  const std::uint16_t port = simulation_->port();
  start_vehicle();
  ASSERT_TRUE(run_until(io_, [&] { return loop_closed(); }));

  simulation_.reset();   // streamer_sim goes away: listening socket and connection close
  ASSERT_TRUE(run_until(io_, [&] { return runner_->stats().disconnects >= 1; }));
  start_streamer(port);  // …and comes back on the same port
  ASSERT_TRUE(run_until(io_, [&] { return runner_->stats().connections >= 2 && loop_closed(); }));
  EXPECT_EQ(simulation_->streamer().stats().connections_accepted, 1u);
}

}  // namespace
}  // namespace ocp
