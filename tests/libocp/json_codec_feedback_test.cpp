#include <gtest/gtest.h>

#include <string>

#include "json_codec_test_support.hpp"
#include "ocp/json_codec.hpp"

namespace ocp {
namespace {

using test::fails_with;
using test::remove_member;
using test::set_member;

VehicleOcpShared sample_feedback() {
  VehicleFeedback feedback;
  feedback.ping_latency_ms = 12;
  feedback.message_latency_roundtrip = 80;
  feedback.ms_since_last_vehicle_data = 7;
  feedback.missing_cameras = std::vector<std::string>{"rear"};
  feedback.sender_fault = {"InputLost"};
  feedback.receiver_fault = {"HighLatency", "InvalidMac"};
  feedback.vehicle_data = VehicleUserData{Position{57.5, 11.25}, RawJson{R"({"speed":1})"}};
  feedback.last_remote_input = Controller::safe_default();
  feedback.ack = {9007199254740993u, 4294967295u};
  feedback.is_monitor = true;
  VehicleOcpShared message;
  message.vehicle_feedback["truck \"1\""] = feedback;
  message.last_input = Controller::safe_default();
  message.last_input->buttons.start = true;
  return message;
}

std::string sample_feedback_text() {
  std::string text;
  encode_vehicle_ocp_shared(sample_feedback(), text);
  return text;
}

constexpr const char* entry_path = "vehicle_feedback.truck \"1\".";

TEST(JsonCodecFeedback, SeedExampleDecodes) {
  const auto message =
      decode_vehicle_ocp_shared(test::read_data_file("seeds/004_vehicle_feedback.derived.json"));
  ASSERT_TRUE(message.ok()) << message.error().message();
  ASSERT_EQ(message->vehicle_feedback.count("truck-1"), 1u);
  const VehicleFeedback& feedback = message->vehicle_feedback.at("truck-1");
  EXPECT_EQ(feedback.ping_latency_ms, 12u);
  EXPECT_EQ(feedback.message_latency_roundtrip, 80u);
  EXPECT_EQ(feedback.missing_cameras, (std::vector<std::string>{"rear"}));
  EXPECT_EQ(feedback.sender_fault, (std::vector<std::string>{"InputLost"}));
  EXPECT_EQ(feedback.receiver_fault, (std::vector<std::string>{"HighLatency"}));
  EXPECT_EQ(feedback.vehicle_data->user_data.text, R"({"speed_mps": 1.4})");
  EXPECT_TRUE(feedback.last_remote_input->buttons.a);
  EXPECT_EQ(feedback.ack, (AckPair{123456, 987654321}));
  EXPECT_FALSE(feedback.is_monitor) << "absent is_monitor means a normal link";
  EXPECT_EQ(message->last_input->axes.right_trigger, 0.5);
}

TEST(JsonCodecFeedback, RoundTripsThroughEncodeAndDecode) {
  const auto decoded = decode_vehicle_ocp_shared(sample_feedback_text());
  ASSERT_TRUE(decoded.ok()) << decoded.error().message();
  EXPECT_EQ(*decoded, sample_feedback());
}

TEST(JsonCodecFeedback, NullableFieldsEncodeAsNullAndDecodeToNullopt) {
  VehicleOcpShared message = sample_feedback();
  VehicleFeedback& feedback = message.vehicle_feedback.begin()->second;
  feedback.message_latency_roundtrip.reset();
  feedback.missing_cameras.reset();
  feedback.vehicle_data.reset();
  feedback.last_remote_input.reset();
  message.last_input.reset();
  std::string text;
  encode_vehicle_ocp_shared(message, text);
  for (const char* field : {"message_latency_roundtrip", "missing_cameras", "vehicle_data",
                            "last_remote_input", "last_input"}) {
    EXPECT_NE(text.find(test::member_prefix(field) + "null"), std::string::npos) << field;
  }
  const auto decoded = decode_vehicle_ocp_shared(text);
  ASSERT_TRUE(decoded.ok());
  EXPECT_EQ(*decoded, message);
}

TEST(JsonCodecFeedback, OptionalFieldsMayBeAbsent) {
  std::string text = sample_feedback_text();
  for (const char* field : {"message_latency_roundtrip", "missing_cameras", "vehicle_data",
                            "last_remote_input", "is_monitor", "last_input"}) {
    text = remove_member(text, field);
  }
  const auto decoded = decode_vehicle_ocp_shared(text);
  ASSERT_TRUE(decoded.ok()) << decoded.error().message();
  const VehicleFeedback& feedback = decoded->vehicle_feedback.begin()->second;
  EXPECT_FALSE(feedback.message_latency_roundtrip.has_value());
  EXPECT_FALSE(feedback.missing_cameras.has_value());
  EXPECT_FALSE(feedback.vehicle_data.has_value());
  EXPECT_FALSE(feedback.last_remote_input.has_value());
  EXPECT_FALSE(feedback.is_monitor);
  EXPECT_FALSE(decoded->last_input.has_value());
}

TEST(JsonCodecFeedback, RequiredEntryFieldsAreReportedWithTheVehicleName) {
  for (const char* field : {"ping_latency_ms", "ms_since_last_vehicle_data", "sender_fault",
                            "receiver_fault", "ack_time", "ack_time_mac"}) {
    SCOPED_TRACE(field);
    EXPECT_TRUE(fails_with(decode_vehicle_ocp_shared(remove_member(sample_feedback_text(), field)),
                           PeerError::missing_field,
                           std::string(entry_path).append(field).append(": required field missing")));
  }
  EXPECT_TRUE(fails_with(decode_vehicle_ocp_shared(remove_member(sample_feedback_text(), "vehicle_feedback")),
                         PeerError::missing_field, "vehicle_feedback: required field missing"));
}

TEST(JsonCodecFeedback, EveryFieldIsTypeChecked) {
  struct Case {
    const char* field;
    const char* value;
    PeerError code;
    const char* message;
  };
  const Case cases[] = {
      {"ping_latency_ms", "-1", PeerError::out_of_range,
       "expected unsigned 64-bit integer, got -1"},
      {"message_latency_roundtrip", "\"80\"", PeerError::wrong_type,
       "expected unsigned 64-bit integer"},
      {"ms_since_last_vehicle_data", "7.5", PeerError::out_of_range,
       "expected unsigned 64-bit integer, got 7.5"},
      {"missing_cameras", "[null]", PeerError::wrong_type, "expected string"},
      {"sender_fault", "null", PeerError::wrong_type, "expected array of strings"},
      {"receiver_fault", "{}", PeerError::wrong_type, "expected array of strings"},
      {"vehicle_data", "[]", PeerError::wrong_type, "expected object"},
      {"last_remote_input", "1", PeerError::wrong_type, "expected object"},
      {"ack_time", "-2", PeerError::out_of_range, "expected unsigned 64-bit integer, got -2"},
      {"ack_time_mac", "4294967296", PeerError::out_of_range,
       "expected unsigned 32-bit integer, got 4294967296"},
      {"is_monitor", "0", PeerError::wrong_type, "expected boolean"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.field);
    const std::string suffix = std::string(c.field) == "missing_cameras" ? "[0]" : "";
    EXPECT_TRUE(fails_with(decode_vehicle_ocp_shared(set_member(sample_feedback_text(), c.field, c.value)),
                           c.code, std::string(entry_path).append(c.field).append(suffix).append(": ").append(c.message)));
  }
  EXPECT_TRUE(fails_with(decode_vehicle_ocp_shared(set_member(sample_feedback_text(), "last_input", "[]")),
                         PeerError::wrong_type, "last_input: expected object"));
  EXPECT_TRUE(fails_with(decode_vehicle_ocp_shared(set_member(sample_feedback_text(), "vehicle_feedback", "[]")),
                         PeerError::wrong_type, "vehicle_feedback: expected object"));
  EXPECT_TRUE(fails_with(decode_vehicle_ocp_shared(set_member(sample_feedback_text(), "vehicle_feedback",
                                                              R"({"t":5})")),
                         PeerError::wrong_type, "vehicle_feedback.t: expected object"));
}

TEST(JsonCodecFeedback, NestedControllerAndVehicleDataErrorsCarryTheFullPath) {
  EXPECT_TRUE(fails_with(decode_vehicle_ocp_shared(set_member(sample_feedback_text(), "start", "1")),
                         PeerError::wrong_type,
                         std::string(entry_path) + "last_remote_input.buttons.start: expected boolean"));
  EXPECT_TRUE(fails_with(decode_vehicle_ocp_shared(remove_member(sample_feedback_text(), "user_data")),
                         PeerError::missing_field,
                         std::string(entry_path) + "vehicle_data.user_data: required field missing"));
}

TEST(JsonCodecFeedback, SeveralVehiclesAndAnEmptyFleetRoundTrip) {
  VehicleOcpShared message = sample_feedback();
  message.vehicle_feedback["b"] = VehicleFeedback{};
  message.vehicle_feedback["ä"] = VehicleFeedback{};
  std::string text;
  encode_vehicle_ocp_shared(message, text);
  auto decoded = decode_vehicle_ocp_shared(text);
  ASSERT_TRUE(decoded.ok()) << decoded.error().message();
  EXPECT_EQ(*decoded, message);

  encode_vehicle_ocp_shared(VehicleOcpShared{}, text);
  EXPECT_EQ(text, R"({"vehicle_feedback":{},"last_input":null})");
  decoded = decode_vehicle_ocp_shared(text);
  ASSERT_TRUE(decoded.ok());
  EXPECT_TRUE(decoded->vehicle_feedback.empty());
}

}  // namespace
}  // namespace ocp
