// The vehicle client's wire behaviour in virtual time, against a minimal fake Streamer over an
// in-memory pipe (and, for the "same call" property, a stream the test drives by hand).
#include <gtest/gtest.h>
#include <rapidjson/document.h>

#include "ocp/framing_diagnosis.hpp"
#include "recording_stream.hpp"
#include "world.hpp"

namespace ocp {
namespace {

using testing::ClientWorld;
using testing::control_frame;
using testing::largest_response_gap;
using testing::ms;
using testing::RecordingStream;
using testing::start_pressed;

Controller full_throttle() {
  Controller controller;
  controller.axes.right_trigger = 1.0;
  return controller;
}

rapidjson::Document parse(const std::string& json) {
  rapidjson::Document document;
  document.Parse(json.c_str());
  EXPECT_FALSE(document.HasParseError()) << json;
  return document;
}

TEST(VehicleClientProtocol, EchoesThePairInsideTheOnBytesCallThatDeliveredTheControlMessage) {
  VirtualExecutor executor;
  VehicleClient client(executor, {}, Logger(executor, "vehicle-client", make_null_sink()));
  auto stream = std::make_shared<RecordingStream>();
  client.attach(stream);
  EXPECT_TRUE(stream->no_delay);

  OcpControlMessage message;
  message.ack = AckPair{123456, 987654321};
  stream->deliver(control_frame(message));
  // No executor step ran: the response was written during deliver().
  const std::vector<VehicleResponseMessage> responses = stream->responses();
  ASSERT_EQ(responses.size(), 1u);
  EXPECT_EQ(responses[0].ack, message.ack);
  EXPECT_EQ(executor.events_run(), 0u);
}

// Once the server has sent one valid control message, the pair is answered before the message
// is validated: a later message that fails validation still gets its pair back, then the
// connection closes as a protocol error. The first message is validated before any answer.
TEST(VehicleClientProtocol, AnswersThePairBeforeValidatingOnceTheServerSpokeOcp) {
  VirtualExecutor executor;
  VehicleClient client(executor, {}, Logger(executor, "vehicle-client", make_null_sink()));
  auto stream = std::make_shared<RecordingStream>();
  client.attach(stream);
  OcpControlMessage message;
  message.ack = AckPair{1, 11};
  stream->deliver(control_frame(message));
  ASSERT_EQ(stream->responses().size(), 1u);

  std::string frame;
  ASSERT_TRUE(append_frame(R"({"ack_time":2,"ack_time_mac":22,"telemetry":"not an object"})", frame));
  stream->deliver(frame);
  const std::vector<VehicleResponseMessage> responses = stream->responses();
  ASSERT_EQ(responses.size(), 2u);
  EXPECT_EQ(responses[1].ack, (AckPair{2, 22}));
  EXPECT_FALSE(client.connected());
  EXPECT_EQ(client.stats().last_disconnect_kind, DisconnectKind::protocol_error);
  EXPECT_EQ(client.stats().control_messages_received, 1u);
}

TEST(VehicleClientProtocol, ValidatesTheFirstControlMessageBeforeAnsweringIt) {
  VirtualExecutor executor;
  VehicleClient client(executor, {}, Logger(executor, "vehicle-client", make_null_sink()));
  auto stream = std::make_shared<RecordingStream>();
  client.attach(stream);
  std::string frame;
  ASSERT_TRUE(append_frame(R"({"ack_time":2,"ack_time_mac":22})", frame));   // no telemetry
  stream->deliver(frame);
  EXPECT_TRUE(stream->written.empty());
  EXPECT_EQ(client.stats().last_disconnect_kind, DisconnectKind::not_an_ocp_server);
}

TEST(VehicleClientProtocol, EchoesOnTheLastByteWhenAFrameArrivesByteByByte) {
  VirtualExecutor executor;
  VehicleClient client(executor, {}, Logger(executor, "vehicle-client", make_null_sink()));
  auto stream = std::make_shared<RecordingStream>();
  client.attach(stream);
  OcpControlMessage message;
  message.ack = AckPair{42, 4242};
  const std::string frame = control_frame(message);
  for (std::size_t index = 0; index + 1 < frame.size(); ++index) stream->deliver(frame.substr(index, 1));
  EXPECT_TRUE(stream->written.empty());
  stream->deliver(frame.substr(frame.size() - 1));
  ASSERT_EQ(stream->responses().size(), 1u);
  EXPECT_EQ(stream->responses()[0].ack, message.ack);
}

TEST(VehicleClientProtocol, EchoesEveryControlMessageAtTheVirtualTimeItArrived) {
  ClientWorld world;
  world.streamer->start_control_loop();
  world.executor.run_for(ms(1000));
  world.streamer->stop_control_loop();

  const auto& sent = world.streamer->sent;
  const auto& responses = world.streamer->responses;
  ASSERT_GE(sent.size(), 100u);
  std::size_t matched = 0;
  for (const auto& control : sent) {
    for (const auto& response : responses) {
      if (response.message.ack == control.ack && response.time == control.time) {
        ++matched;
        break;
      }
    }
  }
  EXPECT_EQ(matched, sent.size());  // every pair came back with zero added delay
  for (const auto& response : responses) EXPECT_TRUE(world.streamer->verify(response.message.ack));
  EXPECT_EQ(world.client->stats().control_messages_received, sent.size());
  EXPECT_EQ(world.client->stats().echo_responses_sent, sent.size());
}

TEST(VehicleClientProtocol, SendsNoKeepAlivesWhileControlArrivesEvery10ms) {
  for (const Micros one_way_delay : {Micros{0}, ms(1), Micros{2'500}}) {
    ClientWorld world({}, PipeOptions{.one_way_delay = one_way_delay});
    world.streamer->start_control_loop();
    world.executor.run_for(ms(1000));
    EXPECT_EQ(world.client->stats().keepalive_responses_sent, 0u) << one_way_delay.count();
    EXPECT_EQ(world.client->stats().responses_sent, world.client->stats().control_messages_received);
  }
}

TEST(VehicleClientProtocol, EchoesLargeAckTimesByteExact) {
  ClientWorld world;
  for (std::uint64_t ack_time : {(1ull << 53) + 1, 18446744073709551615ull, 0ull}) {
    OcpControlMessage message;
    message.ack = world.streamer->issue(ack_time);
    world.streamer->send_control(message, /*keep_pair=*/true);
    world.executor.run_for(ms(1));
    ASSERT_FALSE(world.streamer->responses.empty());
    EXPECT_EQ(world.streamer->responses.back().message.ack, message.ack);
  }
}

TEST(VehicleClientProtocol, SendsNothingBeforeTheFirstControlMessage) {
  ClientWorld world;
  world.executor.run_for(ms(1500));
  EXPECT_EQ(world.streamer->bytes_received(), 0u);
  EXPECT_TRUE(world.client->connected());
}

TEST(VehicleClientProtocol, KeepsRespondingEveryResponsePeriodWhileControlPauses) {
  ClientWorld world;
  world.streamer->start_control_loop();
  world.executor.run_for(ms(100));
  world.streamer->stop_control_loop();
  const SimTime last_control = world.streamer->sent.back().time;
  const AckPair last_pair = world.streamer->sent.back().ack;
  world.executor.run_until(last_control + ms(1900));

  const auto& responses = world.streamer->responses;
  EXPECT_LE(largest_response_gap(responses, world.streamer->sent.front().time), ms(10));
  EXPECT_GE(responses.back().time, last_control + ms(1890));
  EXPECT_EQ(responses.back().message.ack, last_pair);  // keep-alives repeat the latest pair
  EXPECT_GE(world.client->stats().keepalive_responses_sent, 189u);
  EXPECT_TRUE(world.client->connected());
}

TEST(VehicleClientProtocol, ResponsesCarryPositionAndStateWellUnder16KiB) {
  VehicleClientConfig config;
  config.start = Position{48.0, 2.0};
  ClientWorld world(config);
  world.streamer->start_control_loop();
  world.executor.run_for(ms(500));

  ASSERT_FALSE(world.streamer->responses.empty());
  for (const auto& response : world.streamer->responses) {
    ASSERT_TRUE(response.message.vehicle_user_data);
    EXPECT_LT(response.payload_bytes, 1024u);
  }
  const VehicleUserData& data = *world.streamer->responses.back().message.vehicle_user_data;
  ASSERT_TRUE(data.pos);
  EXPECT_DOUBLE_EQ(data.pos->lat, 48.0);
  EXPECT_DOUBLE_EQ(data.pos->lon, 2.0);
  const rapidjson::Document user_data = parse(data.user_data.text);
  for (const char* field : {"speed_mps", "heading_deg", "drive_state", "safe_state", "safety_reasons",
                            "throttle", "brake", "steer", "sequence", "timestamp_ms", "last_latency_ms"}) {
    EXPECT_TRUE(user_data.HasMember(field)) << field;
  }
  EXPECT_STREQ(user_data["drive_state"].GetString(), "disabled");
  EXPECT_TRUE(user_data["safe_state"].GetBool());
  EXPECT_LT(world.client->stats().largest_response_bytes, 1024u);
}

TEST(VehicleClientProtocol, SequenceAndTimestampMarkFreshSamples) {
  ClientWorld world;
  world.streamer->start_control_loop(ms(4));  // faster than the 10 ms model: repeats happen
  world.executor.run_for(ms(200));
  std::int64_t previous_sequence = -1;
  std::int64_t previous_timestamp = -1;
  int repeats = 0;
  for (const auto& response : world.streamer->responses) {
    const rapidjson::Document user_data = parse(response.message.vehicle_user_data->user_data.text);
    const std::int64_t sequence = user_data["sequence"].GetInt64();
    const std::int64_t timestamp = user_data["timestamp_ms"].GetInt64();
    if (sequence == previous_sequence) {
      ++repeats;
      EXPECT_EQ(timestamp, previous_timestamp);
    } else {
      EXPECT_GT(sequence, previous_sequence);
      EXPECT_GT(timestamp, previous_timestamp);
    }
    previous_sequence = sequence;
    previous_timestamp = timestamp;
  }
  EXPECT_GT(repeats, 0);
}

TEST(VehicleClientProtocol, AnEnabledOperatorDrivesTheVehicleNorth) {
  ClientWorld world;
  world.streamer->templ.controller = start_pressed();
  world.streamer->start_control_loop();
  world.executor.run_for(ms(50));
  world.streamer->templ.controller = full_throttle();
  world.executor.run_for(ms(3000));

  EXPECT_EQ(world.client->safety().drive_state, DriveState::enabled);
  EXPECT_FALSE(world.client->safety().safe_state);
  EXPECT_GT(world.client->vehicle().speed_mps, 3.0);
  const VehicleUserData& data = *world.streamer->responses.back().message.vehicle_user_data;
  EXPECT_GT(data.pos->lat, world.config.start.lat);
  EXPECT_STREQ(parse(data.user_data.text)["drive_state"].GetString(), "enabled");
}

TEST(VehicleClientProtocol, TelemetryFaultPutsTheVehicleInTheSafeStateAndStopsIt) {
  ClientWorld world;
  world.streamer->templ.controller = start_pressed();
  world.streamer->start_control_loop();
  world.executor.run_for(ms(50));
  world.streamer->templ.controller = full_throttle();
  world.executor.run_for(ms(2000));
  ASSERT_GT(world.client->vehicle().speed_mps, 1.0);

  // What the Streamer sends during a control-path fault: the default controller + fault flag.
  world.streamer->templ.controller = Controller::safe_default();
  world.streamer->templ.telemetry.fault = true;
  world.streamer->templ.telemetry.fault_reason = "High Latency";
  world.executor.run_for(ms(20));
  EXPECT_TRUE(world.client->safety().safe_state);
  EXPECT_TRUE(world.client->safety().reasons.contains(SafetyReason::telemetry_fault));
  EXPECT_EQ(world.client->safety().drive_state, DriveState::disabled);
  world.executor.run_for(ms(3000));
  EXPECT_EQ(world.client->vehicle().speed_mps, 0.0);
  EXPECT_TRUE(world.client->stats().last_telemetry_fault);
  EXPECT_TRUE(world.client->connected());  // faults are not connection problems
}

TEST(VehicleClientProtocol, WatchdogBrakesWhenControlMessagesStop) {
  VehicleClientConfig config;
  config.safety.watchdog = ms(300);
  ClientWorld world(config);
  world.streamer->templ.controller = start_pressed();
  world.streamer->start_control_loop();
  world.executor.run_for(ms(50));
  world.streamer->templ.controller = full_throttle();
  world.executor.run_for(ms(2000));
  world.streamer->stop_control_loop();
  const SimTime last_control = world.streamer->sent.back().time;

  world.executor.run_until(last_control + ms(290));
  EXPECT_FALSE(world.client->safety().safe_state);
  world.executor.run_until(last_control + ms(310));  // first model tick at or after +300 ms
  EXPECT_TRUE(world.client->safety().reasons.contains(SafetyReason::command_timeout));
  world.executor.run_until(last_control + ms(1900));
  EXPECT_EQ(world.client->vehicle().speed_mps, 0.0);
}

TEST(VehicleClientProtocol, ClosesAndReportsABadControlFrame) {
  ClientWorld world;
  world.streamer->start_control_loop();
  world.executor.run_for(ms(30));
  world.streamer->stop_control_loop();
  world.streamer->send_payload("{\"ack_time\": oops");
  world.executor.run_for(ms(5));

  EXPECT_FALSE(world.client->connected());
  ASSERT_EQ(world.disconnects.size(), 1u);
  EXPECT_NE(world.disconnects[0].find("bad control message"), std::string::npos) << world.disconnects[0];
  EXPECT_EQ(world.client->stats().last_disconnect_kind, DisconnectKind::protocol_error);
  EXPECT_TRUE(world.streamer->closed_by_peer());
}

TEST(VehicleClientProtocol, ReportsNotAnOcpServerWhenTheFirstFrameLengthIsAbsurd) {
  ClientWorld world;
  world.streamer->send_raw("HTTP/1.1 400 Bad Request\r\n\r\n");
  world.executor.run_for(ms(5));
  ASSERT_EQ(world.disconnects.size(), 1u);
  EXPECT_EQ(world.client->stats().last_disconnect_kind, DisconnectKind::not_an_ocp_server);
  EXPECT_NE(world.disconnects[0].find("not an OCP server"), std::string::npos);
  EXPECT_NE(world.disconnects[0].find("HTTP"), std::string::npos) << world.disconnects[0];
}

TEST(VehicleClientProtocol, AFirstFrameJustOverTheLimitIsNotAnOcpServersEvenWithItsHeaderSplit) {
  ClientWorld world;
  const std::string bytes = testing::length_prefix(max_payload_bytes + 1) + R"({"filler":"xxxxxxxx)";
  world.streamer->send_raw(bytes.substr(0, 2));
  world.executor.run_for(ms(1));
  EXPECT_TRUE(world.client->connected());
  world.streamer->send_raw(bytes.substr(2));
  world.executor.run_for(ms(1));
  ASSERT_EQ(world.disconnects.size(), 1u);
  EXPECT_EQ(world.client->stats().last_disconnect_kind, DisconnectKind::not_an_ocp_server);
  EXPECT_EQ(world.disconnects[0], "not an OCP server: first frame declares 16385 bytes (limit 16384); " +
                                      describe_non_ocp_bytes(bytes));
}

TEST(VehicleClientProtocol, ReportsNotAnOcpServerWhenTheFirstFrameIsOtherJson) {
  ClientWorld world;
  world.streamer->send_payload(R"({"hello":"world"})");
  world.executor.run_for(ms(5));
  ASSERT_EQ(world.disconnects.size(), 1u);
  EXPECT_EQ(world.client->stats().last_disconnect_kind, DisconnectKind::not_an_ocp_server);
  EXPECT_NE(world.disconnects[0].find("not an OCP control message"), std::string::npos) << world.disconnects[0];
}

// Issue #19 item 8: a Streamer stopped with SIGSTOP still completes connects, then says
// nothing; silence is not proof of "not an OCP server", so it is not called that.
TEST(VehicleClientProtocol, SaysNoDataFromTheServerWhenNothingArrivesWithinTwoSeconds) {
  ClientWorld world;
  world.executor.run_until(ms(2000) - Micros{1});
  EXPECT_TRUE(world.client->connected());
  world.executor.run_until(ms(2000));
  EXPECT_FALSE(world.client->connected());
  ASSERT_EQ(world.disconnects.size(), 1u);
  EXPECT_EQ(world.client->stats().last_disconnect_kind, DisconnectKind::server_silent);
  EXPECT_EQ(world.disconnects[0], "no data from the server for 2 s after connecting (is it stopped or hung?)");
  EXPECT_EQ(world.disconnects[0].find("not an OCP server"), std::string::npos);
}

TEST(VehicleClientProtocol, APartOfAFirstFrameIsNotCalledNotAnOcpServer) {
  ClientWorld world;
  world.streamer->send_raw(testing::length_prefix(200) + R"({"ack_time":)");
  world.executor.run_until(ms(2000));
  ASSERT_EQ(world.disconnects.size(), 1u);
  EXPECT_EQ(world.client->stats().last_disconnect_kind, DisconnectKind::server_silent);
  EXPECT_EQ(world.disconnects[0],
            "no whole control message from the server for 2 s after connecting (16 bytes arrived: part of a frame)");
}

TEST(VehicleClientProtocol, ClosesWhenControlMessagesStopForTwoSeconds) {
  ClientWorld world;
  world.streamer->start_control_loop();
  world.executor.run_for(ms(100));
  world.streamer->stop_control_loop();
  const SimTime last_control = world.streamer->sent.back().time;
  world.executor.run_until(last_control + ms(2000) - Micros{1});
  EXPECT_TRUE(world.client->connected());
  world.executor.run_until(last_control + ms(2000));
  EXPECT_FALSE(world.client->connected());
  EXPECT_EQ(world.client->stats().last_disconnect_kind, DisconnectKind::server_silent);
}

TEST(VehicleClientProtocol, DrainsAnOversizedControlFrameAndKeepsGoing) {
  ClientWorld world;
  world.streamer->send_control(OcpControlMessage{});
  world.executor.run_for(ms(1));
  world.streamer->send_raw(testing::length_prefix(20000) + std::string(20000, 'x'));
  const AckPair after = world.streamer->send_control(OcpControlMessage{});
  world.executor.run_for(ms(1));

  EXPECT_TRUE(world.client->connected());
  EXPECT_EQ(world.client->stats().oversized_frames_dropped, 1u);
  EXPECT_EQ(world.streamer->responses.back().message.ack, after);
}

TEST(VehicleClientProtocol, WorksAgainAfterTheStreamDropsAndANewOneIsAttached) {
  ClientWorld world;
  world.streamer->templ.controller = start_pressed();
  world.streamer->start_control_loop();
  world.executor.run_for(ms(100));
  ASSERT_EQ(world.client->safety().drive_state, DriveState::enabled);
  world.streamer->stop_control_loop();
  world.streamer->close();
  world.executor.run_for(ms(1));
  EXPECT_FALSE(world.client->connected());
  ASSERT_EQ(world.disconnects.size(), 1u);
  EXPECT_EQ(world.client->stats().last_disconnect_kind, DisconnectKind::peer_closed);

  world.connect();  // what the TCP runner does after its backoff
  world.streamer->start_control_loop();
  world.executor.run_for(ms(100));
  EXPECT_TRUE(world.client->connected());
  EXPECT_EQ(world.client->stats().connections, 2u);
  ASSERT_FALSE(world.streamer->responses.empty());
  EXPECT_EQ(world.streamer->responses.back().message.ack, world.streamer->sent.back().ack);
  // A new session starts disabled: the operator must press start again.
  EXPECT_EQ(world.client->safety().drive_state, DriveState::disabled);
}

TEST(VehicleClientProtocol, HandlesFramesSplitIntoSingleBytes) {
  ClientWorld world({}, PipeOptions{.max_chunk_bytes = 1});
  world.streamer->start_control_loop();
  world.executor.run_for(ms(200));
  world.streamer->stop_control_loop();
  world.executor.run_for(ms(1));
  const auto& sent = world.streamer->sent;
  ASSERT_FALSE(sent.empty());
  EXPECT_EQ(world.client->stats().control_messages_received, sent.size());
  EXPECT_EQ(world.streamer->responses.back().message.ack, sent.back().ack);
  EXPECT_TRUE(world.streamer->decode_errors.empty());
}

TEST(VehicleClientProtocol, DetachClosesWithoutReportingADisconnect) {
  ClientWorld world;
  world.streamer->start_control_loop();
  world.executor.run_for(ms(50));
  world.client->detach();
  world.executor.run_for(ms(50));
  EXPECT_FALSE(world.client->connected());
  EXPECT_TRUE(world.disconnects.empty());
  EXPECT_TRUE(world.streamer->closed_by_peer());
}

TEST(VehicleClientProtocol, RejectsUnusableConfigs) {
  EXPECT_FALSE(validate(VehicleClientConfig{}));
  VehicleClientConfig config;
  config.response_period = Micros{0};
  EXPECT_TRUE(validate(config));
  config = {};
  config.user_data_limit_bytes = 20000;
  EXPECT_TRUE(validate(config));
  config = {};
  config.start.lat = 95.0;
  EXPECT_TRUE(validate(config));
}

}  // namespace
}  // namespace ocp
