// The Player's operator API (:4001) on real loopback sockets, driven in real time by
// PlayerSimulation (the player_sim executable's world: simulated vehicles with the reference
// vehicle client in-process).
#include <gtest/gtest.h>

#include <algorithm>
#include <boost/asio/io_context.hpp>
#include <memory>

#include "endpoint_fixture.hpp"
#include "operator_peer.hpp"
#include "player_app/player_simulation.hpp"
#include "player_app/webview/messages.hpp"
#include "sim_app/common_options.hpp"
#include "vehicle_app/tcp_runner.hpp"
#include "vehicle_client/vehicle_client.hpp"

namespace ocp {
namespace {

using testing::CapturedLog;
using testing::run_until;

using OperatorClient = testing::TcpTestClient<testing::OperatorPeer>;
using TcpClient = testing::TcpTestClient<>;

// The answer of a well-behaved TCP client: the latest pair of each vehicle, returned.
ClientOcpShared echo_all(const VehicleOcpShared& shared, bool with_pairs = true,
                         std::optional<std::string> user_data = std::nullopt) {
  ClientOcpShared answer;
  for (const auto& [name, feedback] : shared.vehicle_feedback) {
    ClientVehicleEntry entry;
    if (with_pairs && feedback.ack.ack_time != 0) {
      entry.ack_time_returned = feedback.ack.ack_time;
      entry.ack_time_mac_returned = feedback.ack.ack_time_mac;
    }
    if (user_data) entry.user_data = RawJson{*user_data};
    answer.client_user_data[name] = entry;
  }
  return answer;
}

class OperatorApi : public ::testing::Test {
 protected:
  void start(std::vector<std::string> vehicles = {"truck-1"}) {
    PlayerSimOptions options;
    options.vehicles = std::move(vehicles);
    options.plugin_params.ocp_player_tcp_port = 0;
    simulation_ = std::make_unique<PlayerSimulation>(executor_, options, log_.sink());
    ASSERT_TRUE(simulation_->start().ok());
    ASSERT_NE(simulation_->port(), 0);
  }
  void TearDown() override { simulation_.reset(); }

  PlayerCore& player() { return simulation_->player(); }
  StreamerCore& streamer(const std::string& name) { return simulation_->world().streamer(name); }

  boost::asio::io_context io_;
  AsioExecutor executor_{io_};
  CapturedLog log_;
  std::unique_ptr<PlayerSimulation> simulation_;
};

TEST_F(OperatorApi, ClientSeesFeedbackForTheVehicleAndItsReturnedPairClosesTheLoop) {
  start();
  OperatorClient client(io_);
  ASSERT_TRUE(client.connect(simulation_->port()));
  ASSERT_TRUE(run_until(io_, [&] {
    const auto found = client.latest().vehicle_feedback.find("truck-1");
    return found != client.latest().vehicle_feedback.end() && found->second.ack.ack_time != 0 &&
           found->second.vehicle_data.has_value();
  }));
  EXPECT_EQ(client.decode_errors, 0u);
  EXPECT_EQ(client.latest().vehicle_feedback.size(), 1u);
  // The reference vehicle's user data crossed the link.
  EXPECT_NE(client.latest().vehicle_feedback.at("truck-1").vehicle_data->user_data.text.find("drive_state"),
            std::string::npos);

  // Before any client data the Player self-echoes: the loop is closed.
  ASSERT_TRUE(run_until(io_, [&] { return !streamer("truck-1").faults().contains(FaultId::InvalidMac); }));

  // Client data without pairs locks the tcp source: self-echo stops, so the loop opens. (It
  // must carry some field: an entry with none is a keep-alive, SPEC §4.2.)
  client.answer = [&](const VehicleOcpShared& shared) { client.send(echo_all(shared, false, R"({"tool":"none"})")); };
  ASSERT_TRUE(run_until(io_, [&] {
    return player().locked_source() == ClientSource::tcp &&
           streamer("truck-1").faults().contains(FaultId::InvalidMac);
  }));

  // Returning the pairs closes it again.
  client.answer = [&](const VehicleOcpShared& shared) { client.send(echo_all(shared, true)); };
  ASSERT_TRUE(run_until(io_, [&] {
    return !streamer("truck-1").faults().contains(FaultId::InvalidMac) &&
           streamer("truck-1").latency_ms().has_value();
  }));
  EXPECT_FALSE(player().client_data_stopped());
}

// SPEC §4.3 Decision: after the locked TCP client leaves, the lock stays and nobody returns
// pairs. The log says so once, the status line every second, the web view status while it lasts.
TEST_F(OperatorApi, LockedTcpClientLeavingIsLoggedAndShownWithTheDecisionsWords) {
  start();
  {
    OperatorClient client(io_);
    ASSERT_TRUE(client.connect(simulation_->port()));
    client.answer = [&](const VehicleOcpShared& shared) { client.send(echo_all(shared, true)); };
    ASSERT_TRUE(run_until(io_, [&] { return player().locked_source() == ClientSource::tcp; }));
    EXPECT_FALSE(player().tcp_lock_without_client());
    EXPECT_EQ(simulation_->status_line().find(tcp_lock_without_client_text), std::string::npos);
  }
  ASSERT_TRUE(run_until(io_, [&] { return player().tcp_lock_without_client(); }));
  const std::string line = simulation_->status_line();
  EXPECT_NE(line.find("operator client none (source tcp locked, no client connected: no pair is returned)"),
            std::string::npos)
      << line;
  EXPECT_TRUE(log_.contains(LogLevel::warn, tcp_lock_without_client_text));
  webview::Status status;
  status.tcp_lock_without_client = std::string(tcp_lock_without_client_text);
  EXPECT_NE(webview::encode_status(status).find(
                R"("tcp_lock_without_client":"source tcp locked, no client connected: no pair is returned")"),
            std::string::npos);
  EXPECT_EQ(webview::encode_status(webview::Status{}).find("tcp_lock_without_client"), std::string::npos);
}

// Issue #20 item 4: player_sim's status line says, per vehicle, why its loop does not close.
TEST_F(OperatorApi, StatusLineSaysWhyAVehiclesLoopDoesNotClose) {
  PlayerSimOptions options;
  options.vehicles = {"truck-1", "truck-2"};
  options.vehicle_tcp_ports = {{"truck-1", 0}};
  options.ack_time_offset = sim_app::high_ack_time_offset;
  options.plugin_params.ocp_player_tcp_port = 0;
  simulation_ = std::make_unique<PlayerSimulation>(executor_, options, log_.sink());
  ASSERT_TRUE(simulation_->start().ok());
  VehicleClientConfig config;
  config.misbehave.ack_through_double = true;
  VehicleClient client(executor_, config, Logger(executor_, "vehicle-client", {}));
  TcpRunnerConfig runner_config;
  runner_config.server.port = simulation_->vehicle_port("truck-1");
  TcpRunner runner(executor_, client, runner_config, Logger(executor_, "tcp", {}));
  runner.start();
  std::string line;
  ASSERT_TRUE(run_until(io_, [&] {
    line = simulation_->status_line();
    return line.find("; loop not closed: ") != std::string::npos;
  }));
  const std::size_t truck_2 = line.find(" | truck-2: ");
  const std::size_t note = line.find("; loop not closed: ");
  ASSERT_NE(truck_2, std::string::npos) << line;
  EXPECT_LT(note, truck_2) << "the note belongs to truck-1: " << line;
  EXPECT_NE(line.find("rounded through a double?", note), std::string::npos) << line;
  EXPECT_EQ(line.find("loop not closed", truck_2), std::string::npos) << "truck-2's loop closes: " << line;
  runner.stop();
}

TEST_F(OperatorApi, DashboardKeepAlivesKeepItConnectedWithoutTakingTheLoop) {
  // SPEC §4.2: `{}` resets the read timer and locks nothing. Sent every 500 ms for 2.5 s: past
  // the 2 s read timeout, with 1.5 s of slack for a loaded machine. The exact timing rule is
  // tested in virtual time (tests/player/keep_alive_test.cpp).
  start();
  OperatorClient dashboard(io_);
  ASSERT_TRUE(dashboard.connect(simulation_->port()));
  ASSERT_TRUE(run_until(io_, [&] {
    const auto& feedback = dashboard.latest().vehicle_feedback;
    const auto found = feedback.find("truck-1");
    return found != feedback.end() && found->second.message_latency_roundtrip.has_value() &&
           found->second.receiver_fault.empty();
  }));
  std::size_t invalid_mac_seen = 0;
  dashboard.answer = [&](const VehicleOcpShared& shared) {
    const auto& faults = shared.vehicle_feedback.at("truck-1").receiver_fault;
    if (std::find(faults.begin(), faults.end(), "InvalidMac") != faults.end()) ++invalid_mac_seen;
  };
  int keep_alives = 0;
  PeriodicTimer keep_alive(executor_, Micros{500'000}, [&](SimTime) {
    dashboard.send(ClientOcpShared{});
    ++keep_alives;
  });
  keep_alive.start(executor_.now());
  ASSERT_TRUE(run_until(io_, [&] { return keep_alives >= 6; }));
  keep_alive.stop();
  testing::run_for(io_, std::chrono::milliseconds(100));
  EXPECT_FALSE(dashboard.closed_by_peer());
  EXPECT_TRUE(player().client_connected());
  EXPECT_EQ(player().locked_source(), std::nullopt);
  EXPECT_GE(player().stats().client_keep_alives, 5u);
  EXPECT_EQ(invalid_mac_seen, 0u);
  EXPECT_FALSE(streamer("truck-1").faults().contains(FaultId::InvalidMac));
}

TEST_F(OperatorApi, ClientUserDataReachesTheVehicle) {
  start();
  // What reached the vehicle: the client_user_data of the control frames the Streamer wrote.
  std::optional<RawJson> last_user_data;
  const auto subscription = streamer("truck-1").events().subscribe([&](const Event& event) {
    const auto* frame = std::get_if<WireFrame>(&event.body);
    if (frame == nullptr || frame->kind != WireMessageKind::control) return;
    if (auto control = decode_control_message(frame->payload); control && control->client_user_data) {
      last_user_data = control->client_user_data;
    }
  });

  OperatorClient client(io_);
  ASSERT_TRUE(client.connect(simulation_->port()));
  client.answer = [&](const VehicleOcpShared& shared) {
    client.send(echo_all(shared, true, std::string(R"({"mission":"dock-7"})")));
  };
  ASSERT_TRUE(run_until(io_, [&] { return last_user_data.has_value(); }));
  EXPECT_EQ(last_user_data->text, R"({"mission":"dock-7"})");
  EXPECT_EQ(player().locked_source(), ClientSource::tcp);
}

TEST_F(OperatorApi, SecondSourceStopsClientData) {
  start();
  OperatorClient client(io_);
  ASSERT_TRUE(client.connect(simulation_->port()));
  client.answer = [&](const VehicleOcpShared& shared) { client.send(echo_all(shared, true)); };
  ASSERT_TRUE(run_until(io_, [&] {
    return player().locked_source() == ClientSource::tcp && !streamer("truck-1").faults().contains(FaultId::InvalidMac) &&
           streamer("truck-1").latency_ms().has_value();
  }));

  // A web view starts sending too: everything stops, the loop visibly breaks.
  ClientOcpShared webview;
  webview.client_user_data["truck-1"].user_data = RawJson{R"({"from":"webview"})"};  // data, not a keep-alive
  player().handle_client_data(ClientSource::webview, webview);
  EXPECT_TRUE(player().client_data_stopped());
  const std::uint64_t ignored = player().stats().client_messages_ignored;
  ASSERT_TRUE(run_until(io_, [&] { return player().stats().client_messages_ignored >= ignored + 10; }));
  ASSERT_TRUE(run_until(io_, [&] { return streamer("truck-1").faults().contains(FaultId::InvalidMac); }));
  EXPECT_TRUE(client.is_open());  // the tcp client is not disconnected for it
}

TEST_F(OperatorApi, SecondClientIsRefusedWhileTheFirstKeepsReceiving) {
  start();
  OperatorClient first(io_);
  ASSERT_TRUE(first.connect(simulation_->port()));
  ASSERT_TRUE(run_until(io_, [&] { return first.received.size() >= 3; }));

  TcpClient second(io_);
  ASSERT_TRUE(second.connect(simulation_->port()));
  ASSERT_TRUE(run_until(io_, [&] { return second.closed_by_peer(); }));
  EXPECT_EQ(player().stats().client_connections_refused, 1u);
  const std::size_t before = first.received.size();
  ASSERT_TRUE(run_until(io_, [&] { return first.received.size() >= before + 20; }));
}

TEST_F(OperatorApi, FleetClientSeesEveryVehicle) {
  start({"truck-1", "truck-2"});
  OperatorClient client(io_);
  ASSERT_TRUE(client.connect(simulation_->port()));
  ASSERT_TRUE(run_until(io_, [&] {
    const auto& feedback = client.latest().vehicle_feedback;
    return feedback.count("truck-1") == 1 && feedback.count("truck-2") == 1 &&
           feedback.at("truck-1").ack.ack_time != 0 && feedback.at("truck-2").ack.ack_time != 0;
  }));
  // No active vehicle selected in a fleet: both report VehicleControlInactive.
  for (const auto& name : {"truck-1", "truck-2"}) {
    const auto& faults = client.latest().vehicle_feedback.at(name).sender_fault;
    EXPECT_NE(std::find(faults.begin(), faults.end(), "VehicleControlInactive"), faults.end()) << name;
  }
}

TEST_F(OperatorApi, MalformedJsonClosesTheClient) {
  start();
  TcpClient client(io_);
  ASSERT_TRUE(client.connect(simulation_->port()));
  ASSERT_TRUE(run_until(io_, [&] { return player().client_connected(); }));
  client.send_payload("[1, 2, 3]");
  ASSERT_TRUE(run_until(io_, [&] { return client.closed_by_peer(); }));
  ASSERT_TRUE(player().last_client_close_reason().has_value());
  EXPECT_EQ(player().last_client_close_reason()->code, PeerError::not_an_object);
}

// Issue #19 item 7: from 17 vehicles up every VehicleOcpShared is over 16 KiB, so the :4001
// client gets nothing (SPEC §2). One WARN was all the user saw; now the status line says it
// every second, and the web view status carries it for the dashboard.
TEST_F(OperatorApi, TwentyVehiclesMakeVehicleOcpSharedTooLargeAndTheStatusLineSaysSo) {
  std::vector<std::string> vehicles;
  for (int k = 1; k <= 20; ++k) vehicles.push_back("truck-" + std::to_string(k));
  start(vehicles);
  TcpClient client(io_);
  ASSERT_TRUE(client.connect(simulation_->port()));
  ASSERT_TRUE(run_until(io_, [&] { return player().client_frame_too_large().has_value(); }));
  const ClientFrameTooLarge too_large = *player().client_frame_too_large();
  EXPECT_GT(too_large.bytes, 16384u);
  EXPECT_EQ(too_large.vehicles, 20u);

  const std::string line = simulation_->status_line();
  EXPECT_NE(line.find("VehicleOcpShared too large: "), std::string::npos) << line;
  EXPECT_NE(line.find(" B > 16384 B, not sent to the client ("), std::string::npos) << line;
  const auto* warning = log_.find(LogLevel::warn, "VehicleOcpShared not sent");
  ASSERT_NE(warning, nullptr);
  EXPECT_NE(warning->message.find("fewer vehicles (20 linked)"), std::string::npos) << warning->message;

  // The web view's status object (ocp_webview_status) as the dashboard reads it.
  webview::Status status;
  status.client_frame_too_large = webview::status_of(too_large);
  const std::string json = webview::encode_status(status);
  EXPECT_NE(json.find(R"("client_frame_too_large":{"bytes":)" + std::to_string(too_large.bytes) +
                      R"(,"limit":16384,"vehicles":20,"text":"VehicleOcpShared too large: )"),
            std::string::npos)
      << json;
  EXPECT_NE(json.find("Reduce the vehicles (20), their vehicle_user_data or cameras."), std::string::npos) << json;
  EXPECT_EQ(webview::encode_status(webview::Status{}).find("client_frame_too_large"), std::string::npos);
}

TEST_F(OperatorApi, PortInUseIsAClearError) {
  start();
  PlayerSimOptions options;
  options.plugin_params.ocp_player_tcp_port = simulation_->port();
  PlayerSimulation second(executor_, options, {});
  const Status status = second.start();
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().code, std::errc::address_in_use);
  EXPECT_EQ(status.error().detail.rfind("another socket listens on 127.0.0.1:" + std::to_string(simulation_->port()) + " (", 0), 0u)
      << status.error().detail;
}

}  // namespace
}  // namespace ocp
