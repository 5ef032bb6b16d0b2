// The web view endpoint of player_sim on real loopback sockets, driven in real time by
// PlayerSimulation: a Beast WebSocket client plays the page, an external vehicle client is
// attached through --vehicle-tcp, a framed TCP client plays the :4001 operator client.
#include <gtest/gtest.h>

#include <algorithm>
#include <boost/asio/io_context.hpp>
#include <memory>

#include "../endpoints/endpoint_fixture.hpp"
#include "ocp/json_codec.hpp"
#include "player_app/player_simulation.hpp"
#include "webview_fixture.hpp"

namespace ocp {
namespace {

using testing::CapturedLog;
using testing::EchoingVehicle;
using testing::TcpTestClient;
using testing::run_for;
using testing::run_until;
using testing::WsClient;

const std::string keep_alive = R"({"name":"ocp_client_user_data","data":{}})";

std::string client_data(const std::string& user_data_json, bool disable_gamepad = true) {
  return R"({"name":"ocp_client_user_data","data":{"active_vehicle":"truck-1","client_user_data":{"truck-1":{"user_data":)" +
         user_data_json + R"(,"ocp_disable_gamepad":)" + (disable_gamepad ? "true" : "false") + "}}}}";
}

class WebviewEndpoint : public ::testing::Test {
 protected:
  // One vehicle, truck-1, whose vehicle API is a real TCP port with an echoing client on it.
  void start(WebviewLimits limits = {}) {
    PlayerSimOptions options;
    options.vehicles = {"truck-1"};
    options.plugin_params.ocp_player_tcp_port = 0;
    options.vehicle_tcp_ports["truck-1"] = 0;
    WebviewOptions webview;
    webview.port = 0;
    webview.root = root_.root;
    webview.limits = limits;
    options.webview = webview;
    simulation_ = std::make_unique<PlayerSimulation>(executor_, options, log_.sink());
    ASSERT_TRUE(simulation_->start().ok());
    ASSERT_NE(simulation_->webview_port(), 0);
    ASSERT_NE(simulation_->vehicle_port("truck-1"), 0);
    ASSERT_TRUE(vehicle_.connect(simulation_->vehicle_port("truck-1")));
  }
  void TearDown() override {
    if (simulation_) simulation_->stop();
  }
  bool wait_frames(WsClient& page, std::size_t count) {
    const std::size_t target = page.count(webview::vehicle_data_name) + count;
    return run_until(io_, [&] { return page.count(webview::vehicle_data_name) >= target; });
  }
  std::size_t log_lines_with(const std::string& needle) const {
    const auto& lines = log_.lines();
    return static_cast<std::size_t>(std::count_if(lines.begin(), lines.end(), [&](const CapturedLog::Line& line) {
      return line.message.find(needle) != std::string::npos;
    }));
  }
  StreamerCore& streamer() { return simulation_->world().streamer("truck-1"); }

  boost::asio::io_context io_;
  AsioExecutor executor_{io_};
  CapturedLog log_;
  testing::TempWebRoot root_;
  EchoingVehicle vehicle_{io_};
  std::unique_ptr<PlayerSimulation> simulation_;
};

TEST_F(WebviewEndpoint, PageReceivesStatusThenVehicleUserDataEveryFrame) {
  start();
  WsClient page(io_);
  ASSERT_TRUE(page.connect(io_, simulation_->webview_port()));
  ASSERT_TRUE(wait_frames(page, 20));
  ASSERT_FALSE(page.messages().empty());
  EXPECT_EQ(page.messages().front().name, webview::status_name);
  EXPECT_NE(page.messages().front().data_json.find(R"("locked_source":null)"), std::string::npos);
  const auto frames = page.data_of(webview::vehicle_data_name);
  auto shared = decode_vehicle_ocp_shared(frames.back());
  ASSERT_TRUE(shared.ok()) << shared.error().message();
  ASSERT_TRUE(shared->vehicle_feedback.contains("truck-1"));
  EXPECT_NE(shared->vehicle_feedback.at("truck-1").ack.ack_time, 0u);
  EXPECT_EQ(simulation_->webview()->websocket_clients(), 1u);
}

TEST_F(WebviewEndpoint, ListenOnlyPageNeverLocksAndTheLoopStaysClosed) {
  start();
  WsClient page(io_);
  ASSERT_TRUE(page.connect(io_, simulation_->webview_port()));
  page.send(keep_alive);
  ASSERT_TRUE(wait_frames(page, 50));
  EXPECT_FALSE(simulation_->player().locked_source().has_value());
  EXPECT_EQ(simulation_->webview()->stats().keep_alives, 1u);
  EXPECT_EQ(simulation_->webview()->stats().client_data_forwarded, 0u);
  // The auto-echo: nobody sends a pair, the loop is closed all the same.
  ASSERT_TRUE(run_until(io_, [&] { return streamer().latency_ms().has_value(); }));
  EXPECT_FALSE(streamer().faults().contains(FaultId::InvalidMac));
}

TEST_F(WebviewEndpoint, ClientDataLocksTheWebviewSourceAndReachesTheVehicle) {
  start();
  WsClient page(io_);
  ASSERT_TRUE(page.connect(io_, simulation_->webview_port()));
  ASSERT_TRUE(wait_frames(page, 5));
  // A page in control sends on every frame; the Player stamps each message with the pair.
  std::size_t answered = 0;
  ASSERT_TRUE(run_until(io_, [&] {
    const std::size_t frames = page.count(webview::vehicle_data_name);
    for (; answered < frames; ++answered) page.send(client_data(R"({"steer":0.5,"tag":"from-page"})"));
    const auto& messages = vehicle_.received;
    return !messages.empty() && messages.back().client_user_data &&
           messages.back().client_user_data->text.find("from-page") != std::string::npos;
  }));
  EXPECT_EQ(simulation_->player().locked_source(), ClientSource::webview);
  EXPECT_FALSE(vehicle_.received.back().controller.has_value());   // ocp_disable_gamepad
  ASSERT_TRUE(run_until(io_, [&] {
    const auto statuses = page.data_of(webview::status_name);
    return statuses.back().find(R"("locked_source":"webview")") != std::string::npos;
  }));
  // Keep answering for a while: the loop is closed through the page's messages.
  run_until(io_, [&] {
    const std::size_t frames = page.count(webview::vehicle_data_name);
    for (; answered < frames; ++answered) page.send(client_data(R"({"steer":0.5})"));
    return frames > 60;
  });
  EXPECT_FALSE(streamer().faults().contains(FaultId::InvalidMac));
  EXPECT_TRUE(streamer().latency_ms().has_value());
}

TEST_F(WebviewEndpoint, WebviewAndTcpClientBothSendingIsASourceConflict) {
  start();
  WsClient page(io_);
  ASSERT_TRUE(page.connect(io_, simulation_->webview_port()));
  page.send(client_data(R"({"steer":0})"));
  ASSERT_TRUE(run_until(io_, [&] { return simulation_->player().locked_source() == ClientSource::webview; }));

  TcpTestClient<> tcp_client(io_);
  ASSERT_TRUE(tcp_client.connect(simulation_->port()));
  ClientOcpShared tcp_data;
  tcp_data.client_user_data["truck-1"].user_data = RawJson{R"({"from":"tcp"})"};
  std::string json;
  encode_client_ocp_shared(tcp_data, json);
  tcp_client.send_payload(json);

  ASSERT_TRUE(run_until(io_, [&] { return simulation_->player().client_data_stopped(); }));
  EXPECT_TRUE(log_.contains("client data source conflict: locked source 'webview', conflicting source 'tcp'"));
  ASSERT_TRUE(run_until(io_, [&] {
    return page.data_of(webview::status_name).back().find(R"("client_data_stopped":true)") != std::string::npos;
  }));
}

TEST_F(WebviewEndpoint, BadMessagesAreDroppedLoggedOnceAndTheConnectionSurvives) {
  start();
  WsClient page(io_);
  ASSERT_TRUE(page.connect(io_, simulation_->webview_port()));
  for (int i = 0; i < 20; ++i) page.send("this is not JSON");
  page.send(R"({"name":"no_such_message","data":1})");
  page.send(R"({"name":"no_such_message","data":2})");
  page.send(R"({"data":{}})");
  page.send(R"({"name":"ocp_client_user_data","data":{"client_user_data":5}})");
  page.send("binary", /*binary=*/true);
  ASSERT_TRUE(run_until(io_, [&] { return simulation_->webview()->stats().messages_dropped >= 25; }));
  EXPECT_EQ(simulation_->webview()->stats().messages_dropped, 25u);
  ASSERT_TRUE(wait_frames(page, 10));   // still connected, still served
  EXPECT_FALSE(page.closed());
  EXPECT_FALSE(simulation_->player().locked_source().has_value());

  EXPECT_EQ(log_lines_with("malformed message dropped"), 1u);
  EXPECT_EQ(log_lines_with("unknown name message dropped: 'no_such_message'"), 1u);
  EXPECT_EQ(log_lines_with("binary message dropped"), 1u);
  EXPECT_EQ(page.count(webview::error_name), 3u);   // the page is told once per kind
  // (A message over 64 KiB closes the page with 1009: webview_hostile_test.cpp.)

  // A good message afterwards still goes through.
  page.send(client_data(R"({"ok":true})"));
  ASSERT_TRUE(run_until(io_, [&] { return simulation_->player().locked_source() == ClientSource::webview; }));
}

TEST_F(WebviewEndpoint, AFloodIsRateLimitedAndSummarisedNotLoggedPerMessage) {
  WebviewLimits limits;
  limits.max_messages_per_second = 100;
  start(limits);
  WsClient page(io_);
  ASSERT_TRUE(page.connect(io_, simulation_->webview_port()));
  for (int i = 0; i < 3000; ++i) page.send(keep_alive);
  ASSERT_TRUE(run_until(io_, [&] { return simulation_->webview()->stats().messages_received +
                                              simulation_->webview()->stats().messages_dropped >= 3000; }));
  const WebviewStats& stats = simulation_->webview()->stats();
  EXPECT_GT(stats.messages_dropped, 2000u);
  EXPECT_LE(stats.keep_alives, 1000u);
  EXPECT_EQ(log_lines_with("over the rate limit message dropped"), 1u);
  ASSERT_TRUE(wait_frames(page, 5));
  EXPECT_FALSE(page.closed());
  // The summary arrives when the page goes away.
  simulation_->webview()->stop();
  EXPECT_EQ(log_lines_with("more messages dropped since the last report"), 1u);
}

TEST_F(WebviewEndpoint, APageThatDoesNotReadIsDisconnectedWithAReason) {
  WebviewLimits limits;
  limits.max_queued_messages = 8;
  limits.socket_send_buffer_bytes = 4096;
  start(limits);
  // Large vehicle user data makes every frame a few KiB, so the buffers fill quickly.
  vehicle_.echo_user_data = VehicleUserData{std::nullopt, RawJson{R"({"blob":")" + std::string(3000, 'v') + R"("})"}};
  WsClient slow(io_);
  ASSERT_TRUE(slow.connect(io_, simulation_->webview_port(), /*read=*/false, /*receive_buffer_bytes=*/4096));
  WsClient good(io_);
  ASSERT_TRUE(good.connect(io_, simulation_->webview_port()));
  ASSERT_TRUE(run_until(io_, [&] { return simulation_->webview()->stats().slow_clients_disconnected == 1; },
                        std::chrono::seconds(30)));
  EXPECT_TRUE(log_.contains("disconnected: not reading: 8 messages waiting for it"));
  ASSERT_TRUE(wait_frames(good, 10));
  EXPECT_EQ(simulation_->webview()->websocket_clients(), 1u);
}

TEST_F(WebviewEndpoint, ClientsOverTheCapAreRefused) {
  WebviewLimits limits;
  limits.max_clients = 2;
  start(limits);
  WsClient first(io_), second(io_), third(io_);
  ASSERT_TRUE(first.connect(io_, simulation_->webview_port()));
  ASSERT_TRUE(second.connect(io_, simulation_->webview_port()));
  EXPECT_FALSE(third.connect(io_, simulation_->webview_port()));
  EXPECT_EQ(simulation_->webview()->stats().websocket_refused, 1u);
  EXPECT_TRUE(log_.contains("2 web view clients already connected"));
  EXPECT_EQ(third.handshake_status(), 503u);
  ASSERT_TRUE(wait_frames(first, 5));
}

TEST_F(WebviewEndpoint, ServesStaticFilesWithContentTypesAndRefusesTraversal) {
  start();
  const std::uint16_t port = simulation_->webview_port();
  auto reply = testing::http_get(io_, port, "/");
  EXPECT_EQ(reply.status, 200u);
  EXPECT_EQ(reply.content_type, "text/html; charset=utf-8");
  EXPECT_NE(reply.body.find("<title>home</title>"), std::string::npos);
  reply = testing::http_get(io_, port, "/app/main.js?v=1");
  EXPECT_EQ(reply.status, 200u);
  EXPECT_EQ(reply.content_type, "text/javascript; charset=utf-8");
  EXPECT_EQ(testing::http_get(io_, port, "/style.css").content_type, "text/css; charset=utf-8");
  EXPECT_EQ(testing::http_get(io_, port, "/missing.html").status, 404u);
  for (const std::string target : {"/../secret.txt", "/app/../../secret.txt", "/%2e%2e/secret.txt",
                                   "/app/%2E%2E%2F%2E%2E%2Fsecret.txt", "/link.txt", "/..%5csecret.txt"}) {
    reply = testing::http_get(io_, port, target);
    EXPECT_EQ(reply.status, 403u) << target;
    EXPECT_EQ(reply.body.find("do not serve"), std::string::npos) << target;
  }
  EXPECT_EQ(testing::http_get(io_, port, "/%zz").status, 400u);
  EXPECT_EQ(log_lines_with("more of these are counted"), 1u);   // one episode of refused paths
  EXPECT_GE(simulation_->webview()->stats().paths_refused, 6u);
}

}  // namespace
}  // namespace ocp
