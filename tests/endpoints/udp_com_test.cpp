// The com channel over UDP (issue #22) on real loopback sockets: streamer_sim's simulation
// with --com-listen and the reference vehicle client, player_sim's with --vehicle
// NAME=udp://…, both on one io_context (two processes differ only by the address space).
// Bounds are generous: "within 10 s" for what takes ~100 ms, so a loaded machine cannot flake.
#include <gtest/gtest.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <cstdio>
#include <fstream>
#include <memory>
#include <random>

#include "endpoint_fixture.hpp"
#include "player_app/player_cli.hpp"
#include "player_app/player_simulation.hpp"
#include "streamer_app/streamer_cli.hpp"
#include "streamer_app/streamer_simulation.hpp"
#include "vehicle_app/tcp_runner.hpp"

namespace ocp {
namespace {

using boost::asio::ip::udp;
using testing::CapturedLog;
using testing::run_for;
using testing::run_until;

const com::ComKey the_key(32, 0x42);

class UdpComChannel : public ::testing::Test {
 protected:
  void start_streamer() {
    StreamerSimOptions options;
    options.plugin_params.tcp_port = 0;
    options.com_listen = udp::endpoint(boost::asio::ip::address_v4::loopback(), 0);
    options.com_key = the_key;
    streamer_ = std::make_unique<StreamerSimulation>(executor_, options, streamer_log_.sink());
    ASSERT_TRUE(streamer_->start().ok());
    client_ = std::make_unique<VehicleClient>(executor_, VehicleClientConfig{},
                                              Logger(executor_, "vehicle-client", streamer_log_.sink()));
    TcpRunnerConfig config;
    config.server.port = streamer_->port();
    runner_ = std::make_unique<TcpRunner>(executor_, *client_, config,
                                          Logger(executor_, "vehicle-client:tcp", streamer_log_.sink()));
    runner_->start();
  }
  void start_player(const com::ComKey& key) {
    PlayerSimOptions options;
    options.plugin_params.ocp_player_tcp_port = 0;
    options.udp_vehicles["vehicle"] = udp::endpoint(boost::asio::ip::address_v4::loopback(), streamer_->com()->local_port());
    options.com_key = key;
    player_ = std::make_unique<PlayerSimulation>(executor_, options, player_log_.sink());
    ASSERT_TRUE(player_->start().ok());
  }
  void TearDown() override {
    if (runner_) runner_->stop();
    runner_.reset();
    client_.reset();
    player_.reset();
    streamer_.reset();
  }
  bool loop_closed() {
    StreamerCore& streamer = streamer_->streamer();
    return streamer.vehicle_connected() && streamer.faults().empty() && streamer.latency_ms().has_value();
  }
  bool player_sees_latency() {
    const auto& feedback = player_->player().last_shared().vehicle_feedback;
    const auto found = feedback.find("vehicle");
    return found != feedback.end() && found->second.message_latency_roundtrip.has_value() &&
           found->second.receiver_fault.empty();
  }

  boost::asio::io_context io_;
  AsioExecutor executor_{io_};
  CapturedLog streamer_log_;
  CapturedLog player_log_;
  std::unique_ptr<StreamerSimulation> streamer_;
  std::unique_ptr<VehicleClient> client_;
  std::unique_ptr<TcpRunner> runner_;
  std::unique_ptr<PlayerSimulation> player_;
};

TEST_F(UdpComChannel, TheLatencyLoopClosesAcrossTheNetwork) {
  start_streamer();
  start_player(the_key);
  ASSERT_TRUE(run_until(io_, [&] { return loop_closed() && player_sees_latency(); })) << streamer_->status_line();
  EXPECT_LT(*streamer_->streamer().latency_ms(), 1000u);
  EXPECT_FALSE(streamer_->streamer().faults().contains(FaultId::InvalidMac));
  EXPECT_EQ(streamer_->com()->opener_counters().bad_mac, 0u);
  EXPECT_GT(player_->com("vehicle")->opener_counters().messages, 0u);
  EXPECT_NE(streamer_->status_line().find("com udp"), std::string::npos);
}

TEST_F(UdpComChannel, AWrongKeyIsRefusedAndNothingGetsIn) {
  start_streamer();
  start_player(com::ComKey(32, 0x43));
  ASSERT_TRUE(run_until(io_, [&] { return streamer_->com()->opener_counters().bad_mac > 10; }));
  run_for(io_, std::chrono::milliseconds(300));
  EXPECT_EQ(streamer_->com()->opener_counters().messages, 0u);
  EXPECT_EQ(streamer_->streamer().stats().operator_messages_received, 0u);
  EXPECT_FALSE(streamer_->streamer().latency_ms().has_value());
  EXPECT_TRUE(streamer_log_.contains(LogLevel::warn, "key does not match"));
  // Said once for the episode, not once per datagram.
  std::size_t said = 0;
  for (const auto& line : streamer_log_.lines()) said += line.message.find("key does not match") != std::string::npos;
  EXPECT_LE(said, 2u);
  // The Player heard nothing either: the Streamer never learnt its address.
  EXPECT_EQ(player_->com("vehicle")->opener_counters().messages, 0u);
}

TEST_F(UdpComChannel, AFloodOfJunkLeavesItRunning) {
  start_streamer();
  start_player(the_key);
  ASSERT_TRUE(run_until(io_, [&] { return loop_closed(); }));
  udp::socket attacker(io_, udp::endpoint(udp::v4(), 0));
  const udp::endpoint target(boost::asio::ip::address_v4::loopback(), streamer_->com()->local_port());
  std::mt19937_64 random(7);
  std::string junk(1300, '\0');
  for (int sent = 0; sent < 100'000; ++sent) {
    const std::size_t length = random() % junk.size();
    for (std::size_t i = 0; i < length; i += 8) junk[i] = static_cast<char>(random());
    if (sent % 3 == 0 && length >= 4) junk[0] = 'O', junk[1] = 'C', junk[2] = 2, junk[3] = 1;   // looks like ours
    boost::system::error_code ignored;
    attacker.send_to(boost::asio::buffer(junk.data(), length), target, 0, ignored);
    if (sent % 500 == 0) io_.poll();   // let the pipeline run meanwhile
  }
  run_for(io_, std::chrono::milliseconds(200));
  EXPECT_GT(streamer_->com()->opener_counters().dropped(), 1'000u);   // the kernel may drop some first
  EXPECT_EQ(streamer_->com()->counters().peer_changes, 0u);            // nobody took the Player's place
  EXPECT_TRUE(run_until(io_, [&] { return loop_closed() && player_sees_latency(); })) << streamer_->status_line();
}

TEST_F(UdpComChannel, ARestartedPlayerOnANewPortIsAnsweredThere) {
  start_streamer();
  start_player(the_key);
  ASSERT_TRUE(run_until(io_, [&] { return loop_closed(); }));
  player_.reset();   // its socket closes; the next one has another port, as after NAT rebinding
  ASSERT_TRUE(run_until(io_, [&] { return streamer_->streamer().faults().contains(FaultId::NoControlMessage); }));
  start_player(the_key);
  EXPECT_TRUE(run_until(io_, [&] { return loop_closed() && player_sees_latency(); })) << streamer_->status_line();
  EXPECT_EQ(streamer_->com()->counters().peer_changes, 1u);
}

TEST_F(UdpComChannel, TwoPlayersWithTheSameKeyDoNotFloodTheLog) {
  start_streamer();
  start_player(the_key);
  ASSERT_TRUE(run_until(io_, [&] { return loop_closed(); }));
  // A second Player with the same key: each completed handshake moves the Streamer's peer (the
  // one left without answers starts a new session after 1 s), back and forth.
  PlayerSimOptions options;
  options.plugin_params.ocp_player_tcp_port = 0;
  options.udp_vehicles["vehicle"] = udp::endpoint(boost::asio::ip::address_v4::loopback(), streamer_->com()->local_port());
  options.com_key = the_key;
  CapturedLog second_log;
  PlayerSimulation second(executor_, options, second_log.sink());
  ASSERT_TRUE(second.start().ok());
  ASSERT_TRUE(run_until(io_, [&] { return streamer_->com()->counters().peer_changes > 3; }));
  std::size_t said = 0;
  for (const auto& line : streamer_log_.lines()) said += line.message.find("the Player is at") != std::string::npos;
  EXPECT_LE(said, 2u);   // the first Player, then the first move of the episode
}

// ---- the command lines ----

int parse_streamer(std::vector<const char*> args) {
  args.insert(args.begin(), "streamer_sim");
  StreamerCli cli;
  const auto exit_code = parse_streamer_cli(static_cast<int>(args.size()), args.data(), cli);
  return exit_code.value_or(-1);
}
int parse_player(std::vector<const char*> args) {
  args.insert(args.begin(), "player_sim");
  PlayerCli cli;
  const auto exit_code = parse_player_cli(static_cast<int>(args.size()), args.data(), cli);
  return exit_code.value_or(-1);
}

TEST(UdpComOptions, AKeyIsRequiredAndChecked) {
  const std::string key_file = ::testing::TempDir() + "udp_com_key";
  { std::ofstream(key_file, std::ios::binary) << std::string(32, 'k'); }
  const std::string short_key = ::testing::TempDir() + "udp_com_short_key";
  { std::ofstream(short_key, std::ios::binary) << "secret"; }
  EXPECT_EQ(parse_streamer({"--com-listen", "127.0.0.1:5000", "--com-key", key_file.c_str()}), -1);
  EXPECT_EQ(parse_streamer({"--com-listen", "127.0.0.1:5000"}), 2);                        // no key
  EXPECT_EQ(parse_streamer({"--com-listen", "127.0.0.1:5000", "--com-key", "/nonexistent/key"}), 2);
  EXPECT_EQ(parse_streamer({"--com-listen", "127.0.0.1:5000", "--com-key", short_key.c_str()}), 2);
  EXPECT_EQ(parse_streamer({"--com-listen", "127.0.0.1:5000", "--com-insecure"}), -1);
  EXPECT_EQ(parse_streamer({"--com-listen", "0.0.0.0:5000", "--com-key", key_file.c_str()}), 2);   // opt-in
  EXPECT_EQ(parse_streamer({"--com-listen", "0.0.0.0:5000", "--com-key", key_file.c_str(), "--com-allow-remote"}), -1);
  EXPECT_EQ(parse_streamer({"--com-listen", "0.0.0.0:5000", "--com-insecure", "--com-allow-remote"}), 2);
  EXPECT_EQ(parse_streamer({"--com-listen", "127.0.0.1:99999", "--com-insecure"}), 2);
  EXPECT_EQ(parse_streamer({"--com-listen", "nohostport", "--com-insecure"}), 2);
  EXPECT_EQ(parse_streamer({"--com-key", key_file.c_str()}), 2);                            // nothing to key
  EXPECT_EQ(parse_player({"--no-webview", "--vehicle", "truck=udp://127.0.0.1:5000", "--com-key", key_file.c_str()}), -1);
  EXPECT_EQ(parse_player({"--no-webview", "--vehicle", "truck=udp://127.0.0.1:5000"}), 2);
  EXPECT_EQ(parse_player({"--no-webview", "--vehicle", "truck=udp://127.0.0.1:0", "--com-insecure"}), 2);
  EXPECT_EQ(parse_player({"--no-webview", "--vehicle", "truck=udp://10.1.2.3:5000", "--com-insecure"}), 2);
  EXPECT_EQ(parse_player({"--no-webview", "--vehicle", "truck=udp://10.1.2.3:5000", "--com-key", key_file.c_str()}), -1);
  std::remove(key_file.c_str());
  std::remove(short_key.c_str());
}

}  // namespace
}  // namespace ocp
