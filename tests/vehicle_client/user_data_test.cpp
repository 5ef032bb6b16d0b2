// The user_data object: valid JSON, every documented field, and a bounded size.
#include "vehicle_client/user_data.hpp"

#include <gtest/gtest.h>
#include <rapidjson/document.h>

#include <limits>

#include "ocp/json_codec.hpp"

namespace ocp {
namespace {

TEST(VehicleClientUserData, IsValidJsonWithEveryDocumentedField) {
  KinematicBicycle model(VehicleParams{}, Position{57.7, 11.9}, 90.0);
  SafetyLayer safety;
  safety.evaluate(Micros{0});
  std::string json;
  encode_user_data(UserDataSample{model.state(), safety.output(), 42, 7, Micros{1'234'567}, nullptr}, json);
  ASSERT_TRUE(validate_raw_json(json).ok()) << json;
  rapidjson::Document document;
  document.Parse(json.c_str());
  ASSERT_TRUE(document.IsObject());
  EXPECT_EQ(document["sequence"].GetUint64(), 7u);
  EXPECT_EQ(document["timestamp_ms"].GetUint64(), 1234u);
  EXPECT_EQ(document["last_latency_ms"].GetUint64(), 42u);
  EXPECT_DOUBLE_EQ(document["heading_deg"].GetDouble(), 90.0);
  EXPECT_STREQ(document["drive_state"].GetString(), "disabled");
  ASSERT_TRUE(document["safety_reasons"].IsArray());
  EXPECT_STREQ(document["safety_reasons"][0].GetString(), "no_control_message");
  EXPECT_FALSE(document.HasMember("misbehave"));
}

TEST(VehicleClientUserData, StaysUnder1KiBInTheWorstCase) {
  KinematicBicycle model(VehicleParams{}, Position{-89.0, -179.999999}, 359.99);
  SafetyOutput output;
  for (std::size_t index = 0; index < safety_reason_count; ++index) {
    output.reasons.set(static_cast<SafetyReason>(index), true);
  }
  output.command = ActuatorCommand{-1.0, -1.0, -1.0};
  Misbehaviour misbehave;
  misbehave.stop_echo = misbehave.corrupt_mac = misbehave.oversized_frames = true;
  misbehave.ack_through_double = misbehave.malformed_json = misbehave.silent = true;
  misbehave.delay_responses = Micros{59'999'999};
  std::string json;
  encode_user_data(UserDataSample{model.state(), output, ~0ull, ~0ull, Micros{INT64_MAX}, &misbehave}, json);
  EXPECT_TRUE(validate_raw_json(json).ok()) << json;
  EXPECT_LT(json.size(), 1024u) << json;
}

// Fixed resolution, not shortest round-trip: mm/s and command units to 0.001, heading and
// odometer to 0.01.
TEST(VehicleClientUserData, NumbersHaveFixedResolution) {
  VehicleState vehicle;
  vehicle.speed_mps = 12.34567;
  vehicle.yaw_rad = 0.0;  // east: compass 90°
  vehicle.odometer_m = 1234.5678;
  SafetyOutput output;
  output.command = ActuatorCommand{0.3, 0.0, -0.1};
  std::string json;
  encode_user_data(UserDataSample{vehicle, output, 0, 1, Micros{0}, nullptr}, json);
  EXPECT_NE(json.find(R"("speed_mps":12.346,"heading_deg":90.00,)"), std::string::npos) << json;
  EXPECT_NE(json.find(R"("throttle":0.300,"brake":0.000,"steer":-0.100,"odometer_m":1234.57,)"),
            std::string::npos)
      << json;
}

TEST(VehicleClientUserData, TinyNegativeValuesPrintAsZero) {
  VehicleState vehicle;
  SafetyOutput output;
  output.command = ActuatorCommand{0.0, 0.0, -0.0004};
  std::string json;
  encode_user_data(UserDataSample{vehicle, output, 0, 1, Micros{0}, nullptr}, json);
  EXPECT_NE(json.find(R"("steer":0.000,)"), std::string::npos) << json;
}

TEST(VehicleClientUserData, NonFiniteNumbersStayValidJson) {
  VehicleState vehicle;
  vehicle.speed_mps = std::numeric_limits<double>::quiet_NaN();
  vehicle.odometer_m = 1e300;  // beyond the fixed-point range: still a JSON number
  SafetyOutput output;
  output.command.throttle = std::numeric_limits<double>::infinity();
  std::string json;
  encode_user_data(UserDataSample{vehicle, output, 0, 1, Micros{0}, nullptr}, json);
  EXPECT_TRUE(validate_raw_json(json).ok()) << json;
  EXPECT_NE(json.find(R"("speed_mps":null,)"), std::string::npos) << json;
  EXPECT_NE(json.find(R"("throttle":null,)"), std::string::npos) << json;
  rapidjson::Document document;
  document.Parse(json.c_str());
  ASSERT_TRUE(document.IsObject()) << json;
  EXPECT_DOUBLE_EQ(document["odometer_m"].GetDouble(), 1e300);
}

}  // namespace
}  // namespace ocp
