#include <gtest/gtest.h>

#include <string>

#include "json_codec_test_support.hpp"
#include "ocp/json_codec.hpp"

namespace ocp {
namespace {

using test::fails_with;
using test::remove_member;
using test::set_member;

ClientOcpShared sample_client_data() {
  ClientOcpShared message;
  message.active_vehicle = "truck-1";
  ClientVehicleEntry entry;
  entry.user_data = RawJson{R"({"steering_mode":"manual"})"};
  entry.ocp_disable_gamepad = true;
  entry.ack_time_returned = 18446744073709551615u;
  entry.ack_time_mac_returned = 987654321;
  message.client_user_data["truck-1"] = entry;
  return message;
}

std::string sample_client_data_text() {
  std::string text;
  encode_client_ocp_shared(sample_client_data(), text);
  return text;
}

TEST(JsonCodecClient, SeedExamplesDecode) {
  auto message =
      decode_client_ocp_shared(test::read_data_file("seeds/003_client_user_data_webview.derived.json"));
  ASSERT_TRUE(message.ok()) << message.error().message();
  EXPECT_EQ(message->active_vehicle, "my_vehicle");
  const ClientVehicleEntry& entry = message->client_user_data.at("my_vehicle");
  EXPECT_EQ(entry.user_data->text, R"({ "steering_mode": "manual" })");
  EXPECT_EQ(entry.ocp_disable_gamepad, false);
  EXPECT_FALSE(entry.ack_time_returned.has_value()) << "the web view sends no returned pair";

  message =
      decode_client_ocp_shared(test::read_data_file("seeds/004_client_user_data_webview.derived.json"));
  ASSERT_TRUE(message.ok()) << message.error().message();
  EXPECT_EQ(message->client_user_data.count("Name of active vehicle"), 1u);
}

TEST(JsonCodecClient, EncodesTheCanonicalCompactForm) {
  EXPECT_EQ(sample_client_data_text(),
            R"({"active_vehicle":"truck-1","client_user_data":{"truck-1":{)"
            R"("user_data":{"steering_mode":"manual"},"ocp_disable_gamepad":true,)"
            R"("ack_time_returned":18446744073709551615,"ack_time_mac_returned":987654321}}})");
  std::string text;
  encode_client_ocp_shared(ClientOcpShared{}, text);
  EXPECT_EQ(text, R"({"client_user_data":{}})");
}

TEST(JsonCodecClient, RoundTripsThroughEncodeAndDecode) {
  const auto decoded = decode_client_ocp_shared(sample_client_data_text());
  ASSERT_TRUE(decoded.ok()) << decoded.error().message();
  EXPECT_EQ(*decoded, sample_client_data());
}

TEST(JsonCodecClient, EveryFieldIsOptionalAndNullMeansAbsent) {
  auto decoded = decode_client_ocp_shared("{}");
  ASSERT_TRUE(decoded.ok());
  EXPECT_EQ(*decoded, ClientOcpShared{});

  std::string all_null = R"({"active_vehicle":null,"client_user_data":{"v":{"user_data":null,)"
                         R"("ocp_disable_gamepad":null,"ack_time_returned":null,)"
                         R"("ack_time_mac_returned":null}}})";
  decoded = decode_client_ocp_shared(all_null);
  ASSERT_TRUE(decoded.ok()) << decoded.error().message();
  EXPECT_FALSE(decoded->active_vehicle.has_value());
  EXPECT_EQ(decoded->client_user_data.at("v"), ClientVehicleEntry{});

  decoded = decode_client_ocp_shared(R"({"client_user_data":null})");
  ASSERT_TRUE(decoded.ok());
  EXPECT_TRUE(decoded->client_user_data.empty());

  for (const char* field :
       {"user_data", "ocp_disable_gamepad", "ack_time_returned", "ack_time_mac_returned"}) {
    SCOPED_TRACE(field);
    const auto without = decode_client_ocp_shared(remove_member(sample_client_data_text(), field));
    ASSERT_TRUE(without.ok());
    EXPECT_NE(without->client_user_data.at("truck-1"), sample_client_data().client_user_data.at("truck-1"));
  }
}

TEST(JsonCodecClient, EveryFieldIsTypeChecked) {
  EXPECT_TRUE(fails_with(decode_client_ocp_shared(set_member(sample_client_data_text(), "active_vehicle", "1")),
                         PeerError::wrong_type, "active_vehicle: expected string"));
  EXPECT_TRUE(fails_with(decode_client_ocp_shared(set_member(sample_client_data_text(), "client_user_data", "[]")),
                         PeerError::wrong_type, "client_user_data: expected object"));
  EXPECT_TRUE(fails_with(decode_client_ocp_shared(set_member(sample_client_data_text(), "truck-1", "true")),
                         PeerError::wrong_type, "client_user_data.truck-1: expected object"));
  EXPECT_TRUE(fails_with(
      decode_client_ocp_shared(set_member(sample_client_data_text(), "ocp_disable_gamepad", "\"yes\"")),
      PeerError::wrong_type, "client_user_data.truck-1.ocp_disable_gamepad: expected boolean"));
  EXPECT_TRUE(fails_with(
      decode_client_ocp_shared(set_member(sample_client_data_text(), "ack_time_returned", "18446744073709551616")),
      PeerError::out_of_range,
      "client_user_data.truck-1.ack_time_returned: expected unsigned 64-bit integer, got "
      "18446744073709551616"));
  EXPECT_TRUE(fails_with(
      decode_client_ocp_shared(set_member(sample_client_data_text(), "ack_time_returned", "\"1\"")),
      PeerError::wrong_type,
      "client_user_data.truck-1.ack_time_returned: expected unsigned 64-bit integer"));
  EXPECT_TRUE(fails_with(
      decode_client_ocp_shared(set_member(sample_client_data_text(), "ack_time_mac_returned", "1.5")),
      PeerError::out_of_range,
      "client_user_data.truck-1.ack_time_mac_returned: expected unsigned 32-bit integer, got 1.5"));
  EXPECT_TRUE(fails_with(
      decode_client_ocp_shared(set_member(sample_client_data_text(), "ack_time_mac_returned", "false")),
      PeerError::wrong_type,
      "client_user_data.truck-1.ack_time_mac_returned: expected unsigned 32-bit integer"));
}

TEST(JsonCodecClient, UserDataIsCarriedByteExact) {
  const std::string user_data = R"([ 1e2, -0.0, 18446744073709551616, "\ud83d\ude00" ])";
  const auto decoded = decode_client_ocp_shared(set_member(sample_client_data_text(), "user_data", user_data));
  ASSERT_TRUE(decoded.ok()) << decoded.error().message();
  EXPECT_EQ(decoded->client_user_data.at("truck-1").user_data->text, user_data);
}

TEST(JsonCodecClient, DuplicateVehicleNamesKeepTheLastEntry) {
  const auto decoded = decode_client_ocp_shared(
      R"({"client_user_data":{"v":{"ocp_disable_gamepad":true},"v":{"ack_time_returned":3}}})");
  ASSERT_TRUE(decoded.ok());
  const ClientVehicleEntry& entry = decoded->client_user_data.at("v");
  EXPECT_FALSE(entry.ocp_disable_gamepad.has_value());
  EXPECT_EQ(entry.ack_time_returned, 3u);
}

TEST(JsonCodecClient, UnknownFieldsAreIgnored) {
  std::string text = sample_client_data_text();
  text = test::replace_once(text, "{\"active_vehicle\":", R"({"version":[1],"active_vehicle":)");
  text = test::replace_once(text, "{\"user_data\":", R"({"color":"red","user_data":)");
  const auto decoded = decode_client_ocp_shared(text);
  ASSERT_TRUE(decoded.ok()) << decoded.error().message();
  EXPECT_EQ(*decoded, sample_client_data());
}

}  // namespace
}  // namespace ocp
