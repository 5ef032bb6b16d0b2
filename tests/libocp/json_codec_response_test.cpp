#include <gtest/gtest.h>

#include <string>

#include "json_codec_test_support.hpp"
#include "ocp/json_codec.hpp"

namespace ocp {
namespace {

using test::fails_with;
using test::remove_member;
using test::set_member;

VehicleResponseMessage sample_response() {
  VehicleResponseMessage message;
  message.ack = {18446744073709551615u, 4294967295u};
  message.vehicle_user_data = VehicleUserData{Position{57.7089, 11.9746},
                                              RawJson{R"({"speed_mps":1.4})"}};
  return message;
}

std::string sample_response_text() {
  std::string text;
  encode_vehicle_response(sample_response(), text);
  return text;
}

TEST(JsonCodecResponse, SeedMinimalResponseDecodes) {
  const auto message =
      decode_vehicle_response(test::read_data_file("seeds/000_response_minimal.json"));
  ASSERT_TRUE(message.ok()) << message.error().message();
  EXPECT_EQ(message->ack, (AckPair{123456, 987654321}));
  EXPECT_FALSE(message->vehicle_user_data.has_value());
}

TEST(JsonCodecResponse, SeedResponseWithVehicleDataDecodes) {
  const auto message =
      decode_vehicle_response(test::read_data_file("seeds/000_response_with_vehicle_data.json"));
  ASSERT_TRUE(message.ok()) << message.error().message();
  EXPECT_EQ(message->ack, (AckPair{123456, 987654321}));
  ASSERT_TRUE(message->vehicle_user_data.has_value());
  EXPECT_EQ(message->vehicle_user_data->pos, (Position{57.7089, 11.9746}));
  EXPECT_EQ(message->vehicle_user_data->user_data.text,
            "{\n      \"speed_mps\": 1.4,\n      \"drive_state\": \"enabled\"\n    }");
}

TEST(JsonCodecResponse, EncodesTheCanonicalCompactForm) {
  EXPECT_EQ(sample_response_text(),
            R"({"ack_time":18446744073709551615,"ack_time_mac":4294967295,)"
            R"("vehicle_user_data":{"pos":{"lat":57.7089,"lon":11.9746},)"
            R"("user_data":{"speed_mps":1.4}}})");
  VehicleResponseMessage minimal;
  minimal.ack = {1, 2};
  std::string text;
  encode_vehicle_response(minimal, text);
  EXPECT_EQ(text, R"({"ack_time":1,"ack_time_mac":2})");
}

TEST(JsonCodecResponse, RoundTripsThroughEncodeAndDecode) {
  const auto decoded = decode_vehicle_response(sample_response_text());
  ASSERT_TRUE(decoded.ok()) << decoded.error().message();
  EXPECT_EQ(*decoded, sample_response());
}

TEST(JsonCodecResponse, AckPairIsRequiredAndTyped) {
  EXPECT_TRUE(fails_with(decode_vehicle_response(remove_member(sample_response_text(), "ack_time")),
                         PeerError::missing_field, "ack_time: required field missing"));
  EXPECT_TRUE(fails_with(decode_vehicle_response(remove_member(sample_response_text(), "ack_time_mac")),
                         PeerError::missing_field, "ack_time_mac: required field missing"));
  EXPECT_TRUE(fails_with(decode_vehicle_response(set_member(sample_response_text(), "ack_time", "1.0")),
                         PeerError::out_of_range,
                         "ack_time: expected unsigned 64-bit integer, got 1.0"));
  EXPECT_TRUE(fails_with(decode_vehicle_response(set_member(sample_response_text(), "ack_time", "true")),
                         PeerError::wrong_type, "ack_time: expected unsigned 64-bit integer"));
  EXPECT_TRUE(
      fails_with(decode_vehicle_response(set_member(sample_response_text(), "ack_time_mac", "-5")),
                 PeerError::out_of_range, "ack_time_mac: expected unsigned 32-bit integer, got -5"));
  EXPECT_TRUE(
      fails_with(decode_vehicle_response(set_member(sample_response_text(), "ack_time_mac", "\"5\"")),
                 PeerError::wrong_type, "ack_time_mac: expected unsigned 32-bit integer"));
}

TEST(JsonCodecResponse, AckTimeAboveTwoToThe53SurvivesExactly) {
  const std::string json = set_member(sample_response_text(), "ack_time", "9007199254740993");
  const auto decoded = decode_vehicle_response(json);
  ASSERT_TRUE(decoded.ok());
  EXPECT_EQ(decoded->ack.ack_time, 9007199254740993u);
  std::string encoded;
  encode_vehicle_response(*decoded, encoded);
  EXPECT_EQ(encoded, json);
}

TEST(JsonCodecResponse, VehicleUserDataIsOptionalAndNullMeansAbsent) {
  auto decoded = decode_vehicle_response(remove_member(sample_response_text(), "vehicle_user_data"));
  ASSERT_TRUE(decoded.ok());
  EXPECT_FALSE(decoded->vehicle_user_data.has_value());
  decoded = decode_vehicle_response(set_member(sample_response_text(), "vehicle_user_data", "null"));
  ASSERT_TRUE(decoded.ok());
  EXPECT_FALSE(decoded->vehicle_user_data.has_value());
  EXPECT_TRUE(fails_with(
      decode_vehicle_response(set_member(sample_response_text(), "vehicle_user_data", "\"x\"")),
      PeerError::wrong_type, "vehicle_user_data: expected object"));
}

TEST(JsonCodecResponse, UserDataIsRequiredAndMayBeAnyJsonValue) {
  EXPECT_TRUE(fails_with(decode_vehicle_response(remove_member(sample_response_text(), "user_data")),
                         PeerError::missing_field,
                         "vehicle_user_data.user_data: required field missing"));
  for (const char* value : {"null", "3", "\"s\"", "[true]", R"({"n":18446744073709551617})"}) {
    SCOPED_TRACE(value);
    const auto decoded = decode_vehicle_response(set_member(sample_response_text(), "user_data", value));
    ASSERT_TRUE(decoded.ok());
    EXPECT_EQ(decoded->vehicle_user_data->user_data.text, value);
  }
}

TEST(JsonCodecResponse, PosIsOptionalOrNullElseNeedsNumericLatAndLon) {
  auto decoded = decode_vehicle_response(remove_member(sample_response_text(), "pos"));
  ASSERT_TRUE(decoded.ok());
  EXPECT_FALSE(decoded->vehicle_user_data->pos.has_value());
  decoded = decode_vehicle_response(set_member(sample_response_text(), "pos", "null"));
  ASSERT_TRUE(decoded.ok());
  EXPECT_FALSE(decoded->vehicle_user_data->pos.has_value());

  EXPECT_TRUE(fails_with(decode_vehicle_response(set_member(sample_response_text(), "pos", "[]")),
                         PeerError::wrong_type, "vehicle_user_data.pos: expected object"));
  EXPECT_TRUE(fails_with(decode_vehicle_response(remove_member(sample_response_text(), "lat")),
                         PeerError::missing_field,
                         "vehicle_user_data.pos.lat: required field missing"));
  EXPECT_TRUE(fails_with(decode_vehicle_response(remove_member(sample_response_text(), "lon")),
                         PeerError::missing_field,
                         "vehicle_user_data.pos.lon: required field missing"));
  EXPECT_TRUE(fails_with(decode_vehicle_response(set_member(sample_response_text(), "lat", "\"57\"")),
                         PeerError::wrong_type, "vehicle_user_data.pos.lat: expected number"));
  EXPECT_TRUE(fails_with(decode_vehicle_response(set_member(sample_response_text(), "lon", "null")),
                         PeerError::wrong_type, "vehicle_user_data.pos.lon: expected number"));
}

TEST(JsonCodecResponse, EncoderWritesNullPosAndNullForEmptyUserData) {
  VehicleResponseMessage message;
  message.ack = {5, 6};
  message.vehicle_user_data = VehicleUserData{};
  std::string text;
  encode_vehicle_response(message, text);
  EXPECT_EQ(text, R"({"ack_time":5,"ack_time_mac":6,"vehicle_user_data":{"pos":null,"user_data":null}})");
  EXPECT_TRUE(decode_vehicle_response(text).ok());
}

TEST(JsonCodecResponse, UnknownFieldsAreIgnored) {
  std::string text = sample_response_text();
  text = test::replace_once(text, "{\"ack_time\":", R"({"v":2,"ack_time":)");
  text = test::replace_once(text, "{\"pos\":", R"({"extra":{},"pos":)");
  text = test::replace_once(text, "{\"lat\":", R"({"alt":12.5,"lat":)");
  const auto decoded = decode_vehicle_response(text);
  ASSERT_TRUE(decoded.ok()) << decoded.error().message();
  EXPECT_EQ(*decoded, sample_response());
}

}  // namespace
}  // namespace ocp
