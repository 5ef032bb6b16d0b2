#include <gtest/gtest.h>

#include <string>

#include "json_codec_test_support.hpp"
#include "ocp/json_codec.hpp"

namespace ocp {
namespace {

using test::fails_with;
using test::remove_member;
using test::set_member;

constexpr const char* button_names[] = {"a",         "b",          "x",           "y",
                                        "left_bumper", "right_bumper", "back",     "start",
                                        "guide",     "left_thumb", "right_thumb", "dpad_up",
                                        "dpad_right", "dpad_down",  "dpad_left"};
constexpr const char* axis_names[] = {"left_x",  "left_y",       "right_x",
                                      "right_y", "left_trigger", "right_trigger"};

OcpControlMessage sample_control() {
  OcpControlMessage message;
  message.controller = Controller::safe_default();
  message.controller->buttons.a = true;
  message.controller->axes.left_x = 0.25;
  message.telemetry.latency_ms = 42;
  message.telemetry.fault = true;
  message.telemetry.fault_reason = "High Latency, Camera Lost";
  message.telemetry.missing_cameras = {"front", "rear"};
  message.ack = {123456, 987654321};
  message.client_user_data = RawJson{R"({"mode":"manual"})"};
  return message;
}

std::string sample_control_text() {
  std::string text;
  encode_control_message(sample_control(), text);
  return text;
}

TEST(JsonCodecControl, SeedExampleDecodes) {
  const std::string json = test::read_data_file("seeds/000_control_message.json");
  const auto message = decode_control_message(json);
  ASSERT_TRUE(message.ok()) << message.error().message();
  ASSERT_TRUE(message->controller.has_value());
  EXPECT_TRUE(message->controller->is_safe_default());
  EXPECT_EQ(message->telemetry.latency_ms, 42u);
  EXPECT_FALSE(message->telemetry.fault);
  EXPECT_EQ(message->telemetry.fault_reason, "");
  EXPECT_TRUE(message->telemetry.missing_cameras.empty());
  EXPECT_EQ(message->ack, (AckPair{123456, 987654321}));
  ASSERT_TRUE(message->client_user_data.has_value());
  // The exact source bytes, whitespace included.
  EXPECT_EQ(message->client_user_data->text, "{\n    \"mode\": \"manual\"\n  }");
}

TEST(JsonCodecControl, EncodesTheCanonicalCompactForm) {
  EXPECT_EQ(sample_control_text(),
            R"({"controller":{"buttons":{"a":true,"b":false,"x":false,"y":false,)"
            R"("left_bumper":false,"right_bumper":false,"back":false,"start":false,)"
            R"("guide":false,"left_thumb":false,"right_thumb":false,"dpad_up":false,)"
            R"("dpad_right":false,"dpad_down":false,"dpad_left":false},)"
            R"("axes":{"left_x":0.25,"left_y":0.0,"right_x":0.0,"right_y":0.0,)"
            R"("left_trigger":-1.0,"right_trigger":-1.0}},)"
            R"("telemetry":{"latency":42,"fault":true,"fault_reason":"High Latency, Camera Lost",)"
            R"("missing_cameras":["front","rear"]},"ack_time":123456,"ack_time_mac":987654321,)"
            R"("client_user_data":{"mode":"manual"}})");
}

TEST(JsonCodecControl, RoundTripsThroughEncodeAndDecode) {
  const auto decoded = decode_control_message(sample_control_text());
  ASSERT_TRUE(decoded.ok()) << decoded.error().message();
  EXPECT_EQ(*decoded, sample_control());
}

TEST(JsonCodecControl, EncoderClearsTheOutputBufferFirst) {
  std::string out = "stale";
  encode_control_message(sample_control(), out);
  EXPECT_EQ(out, sample_control_text());
}

TEST(JsonCodecControl, NullControllerEncodesAsNullAndDecodesToNullopt) {
  OcpControlMessage message = sample_control();
  message.controller.reset();
  std::string text;
  encode_control_message(message, text);
  EXPECT_NE(text.find(R"("controller":null)"), std::string::npos);
  const auto decoded = decode_control_message(text);
  ASSERT_TRUE(decoded.ok());
  EXPECT_FALSE(decoded->controller.has_value());
}

TEST(JsonCodecControl, AbsentControllerDecodesToNullopt) {
  const auto decoded = decode_control_message(remove_member(sample_control_text(), "controller"));
  ASSERT_TRUE(decoded.ok()) << decoded.error().message();
  EXPECT_FALSE(decoded->controller.has_value());
}

TEST(JsonCodecControl, ControllerOfWrongTypeFails) {
  EXPECT_TRUE(fails_with(decode_control_message(set_member(sample_control_text(), "controller", "[]")),
                         PeerError::wrong_type, "controller: expected object"));
}

TEST(JsonCodecControl, ControllerNeedsButtonsAndAxes) {
  EXPECT_TRUE(fails_with(decode_control_message(remove_member(sample_control_text(), "buttons")),
                         PeerError::missing_field,
                         "controller.buttons: required field missing"));
  EXPECT_TRUE(fails_with(decode_control_message(remove_member(sample_control_text(), "axes")),
                         PeerError::missing_field, "controller.axes: required field missing"));
  EXPECT_TRUE(fails_with(decode_control_message(set_member(sample_control_text(), "axes", "true")),
                         PeerError::wrong_type, "controller.axes: expected object"));
}

TEST(JsonCodecControl, EveryButtonIsARequiredBoolean) {
  for (const char* name : button_names) {
    SCOPED_TRACE(name);
    const std::string path = std::string("controller.buttons.") + name;
    EXPECT_TRUE(fails_with(decode_control_message(remove_member(sample_control_text(), name)),
                           PeerError::missing_field, path + ": required field missing"));
    EXPECT_TRUE(fails_with(decode_control_message(set_member(sample_control_text(), name, "1")),
                           PeerError::wrong_type, path + ": expected boolean"));
    EXPECT_TRUE(fails_with(decode_control_message(set_member(sample_control_text(), name, "null")),
                           PeerError::wrong_type, path + ": expected boolean"));
    const auto released = decode_control_message(set_member(sample_control_text(), name, "false"));
    ASSERT_TRUE(released.ok());
    const auto pressed = decode_control_message(set_member(sample_control_text(), name, "true"));
    ASSERT_TRUE(pressed.ok());
    EXPECT_NE(pressed->controller->buttons, released->controller->buttons);
  }
}

TEST(JsonCodecControl, EveryAxisIsARequiredNumber) {
  for (std::size_t axis = 0; axis < std::size(axis_names); ++axis) {
    const char* name = axis_names[axis];
    SCOPED_TRACE(name);
    const std::string path = std::string("controller.axes.") + name;
    EXPECT_TRUE(fails_with(decode_control_message(remove_member(sample_control_text(), name)),
                           PeerError::missing_field, path + ": required field missing"));
    EXPECT_TRUE(fails_with(decode_control_message(set_member(sample_control_text(), name, "\"0.5\"")),
                           PeerError::wrong_type, path + ": expected number"));
    const auto decoded = decode_control_message(set_member(sample_control_text(), name, "-0.75"));
    ASSERT_TRUE(decoded.ok());
    const Axes& axes = decoded->controller->axes;
    const double values[] = {axes.left_x,  axes.left_y,       axes.right_x,
                             axes.right_y, axes.left_trigger, axes.right_trigger};
    EXPECT_EQ(values[axis], -0.75);
  }
}

TEST(JsonCodecControl, AxesAcceptIntegerAndExponentForms) {
  auto decoded = decode_control_message(set_member(sample_control_text(), "left_y", "1"));
  ASSERT_TRUE(decoded.ok());
  EXPECT_EQ(decoded->controller->axes.left_y, 1.0);
  decoded = decode_control_message(set_member(sample_control_text(), "left_y", "-5E-1"));
  ASSERT_TRUE(decoded.ok());
  EXPECT_EQ(decoded->controller->axes.left_y, -0.5);
  decoded = decode_control_message(set_member(sample_control_text(), "left_y", "1e-400"));
  ASSERT_TRUE(decoded.ok()) << "underflow reads as zero";
  EXPECT_EQ(decoded->controller->axes.left_y, 0.0);
}

TEST(JsonCodecControl, DoublesRoundTripExactly) {
  OcpControlMessage message = sample_control();
  const double values[] = {0.1, -0.3333333333333333, 1e-300, 5e-324, 0.7071067811865476,
                           -1.0, 1.7976931348623157e308};
  for (const double value : values) {
    message.controller->axes.right_y = value;
    std::string text;
    encode_control_message(message, text);
    const auto decoded = decode_control_message(text);
    ASSERT_TRUE(decoded.ok()) << text;
    EXPECT_EQ(decoded->controller->axes.right_y, value) << text;
  }
}

TEST(JsonCodecControl, TelemetryIsRequired) {
  EXPECT_TRUE(fails_with(decode_control_message(remove_member(sample_control_text(), "telemetry")),
                         PeerError::missing_field, "telemetry: required field missing"));
  EXPECT_TRUE(fails_with(decode_control_message(set_member(sample_control_text(), "telemetry", "null")),
                         PeerError::wrong_type, "telemetry: expected object"));
}

TEST(JsonCodecControl, TelemetryFieldsAreRequiredAndTyped) {
  EXPECT_TRUE(fails_with(decode_control_message(remove_member(sample_control_text(), "latency")),
                         PeerError::missing_field, "telemetry.latency: required field missing"));
  EXPECT_TRUE(fails_with(decode_control_message(remove_member(sample_control_text(), "fault")),
                         PeerError::missing_field, "telemetry.fault: required field missing"));
  EXPECT_TRUE(fails_with(decode_control_message(remove_member(sample_control_text(), "fault_reason")),
                         PeerError::missing_field,
                         "telemetry.fault_reason: required field missing"));
  EXPECT_TRUE(fails_with(decode_control_message(set_member(sample_control_text(), "fault", "\"no\"")),
                         PeerError::wrong_type, "telemetry.fault: expected boolean"));
  EXPECT_TRUE(fails_with(decode_control_message(set_member(sample_control_text(), "fault_reason", "0")),
                         PeerError::wrong_type, "telemetry.fault_reason: expected string"));
  EXPECT_TRUE(fails_with(decode_control_message(set_member(sample_control_text(), "latency", "\"42\"")),
                         PeerError::wrong_type,
                         "telemetry.latency: expected non-negative integer"));
}

TEST(JsonCodecControl, LatencyAcceptsWholeNumbersOnly) {
  auto decoded = decode_control_message(set_member(sample_control_text(), "latency", "42.0"));
  ASSERT_TRUE(decoded.ok());
  EXPECT_EQ(decoded->telemetry.latency_ms, 42u);
  decoded = decode_control_message(set_member(sample_control_text(), "latency", "18446744073709551615"));
  ASSERT_TRUE(decoded.ok());
  EXPECT_EQ(decoded->telemetry.latency_ms, 18446744073709551615u);
  EXPECT_TRUE(fails_with(decode_control_message(set_member(sample_control_text(), "latency", "42.5")),
                         PeerError::out_of_range,
                         "telemetry.latency: expected non-negative integer, got 42.5"));
  EXPECT_TRUE(fails_with(decode_control_message(set_member(sample_control_text(), "latency", "-1")),
                         PeerError::out_of_range,
                         "telemetry.latency: expected non-negative integer, got -1"));
}

TEST(JsonCodecControl, MissingCamerasIsAnOptionalArrayOfStrings) {
  auto decoded = decode_control_message(remove_member(sample_control_text(), "missing_cameras"));
  ASSERT_TRUE(decoded.ok());
  EXPECT_TRUE(decoded->telemetry.missing_cameras.empty());
  decoded = decode_control_message(set_member(sample_control_text(), "missing_cameras", "[]"));
  ASSERT_TRUE(decoded.ok());
  EXPECT_TRUE(decoded->telemetry.missing_cameras.empty());
  EXPECT_TRUE(fails_with(
      decode_control_message(set_member(sample_control_text(), "missing_cameras", R"(["a",2])")),
      PeerError::wrong_type, "telemetry.missing_cameras[1]: expected string"));
  EXPECT_TRUE(fails_with(
      decode_control_message(set_member(sample_control_text(), "missing_cameras", R"("front")")),
      PeerError::wrong_type, "telemetry.missing_cameras: expected array of strings"));
}

TEST(JsonCodecControl, AckTimeCoversTheFullU64RangeByteExact) {
  for (const char* text : {"0", "9007199254740993", "18446744073709551615"}) {
    SCOPED_TRACE(text);
    const std::string json = set_member(sample_control_text(), "ack_time", text);
    const auto decoded = decode_control_message(json);
    ASSERT_TRUE(decoded.ok());
    EXPECT_EQ(decoded->ack.ack_time, std::stoull(text));
    std::string encoded;
    encode_control_message(*decoded, encoded);
    EXPECT_EQ(encoded, json);
  }
}

TEST(JsonCodecControl, AckTimeRejectsEverythingButAnUnsignedInteger) {
  const std::string expected = "ack_time: expected unsigned 64-bit integer";
  for (const char* text : {"18446744073709551616", "-1", "-0", "1.5", "123.0", "1e5", "1E+2"}) {
    SCOPED_TRACE(text);
    // 123.0 is rejected on purpose: an opaque integer must arrive in integer form.
    EXPECT_TRUE(fails_with(decode_control_message(set_member(sample_control_text(), "ack_time", text)),
                           PeerError::out_of_range, expected + ", got " + text));
  }
  EXPECT_TRUE(fails_with(decode_control_message(set_member(sample_control_text(), "ack_time", "\"1\"")),
                         PeerError::wrong_type, expected));
  EXPECT_TRUE(fails_with(decode_control_message(set_member(sample_control_text(), "ack_time", "null")),
                         PeerError::wrong_type, expected));
  EXPECT_TRUE(fails_with(decode_control_message(remove_member(sample_control_text(), "ack_time")),
                         PeerError::missing_field, "ack_time: required field missing"));
}

TEST(JsonCodecControl, AckTimeMacIsAnUnsigned32BitInteger) {
  const std::string json = set_member(sample_control_text(), "ack_time_mac", "4294967295");
  const auto decoded = decode_control_message(json);
  ASSERT_TRUE(decoded.ok());
  EXPECT_EQ(decoded->ack.ack_time_mac, 4294967295u);
  std::string encoded;
  encode_control_message(*decoded, encoded);
  EXPECT_EQ(encoded, json);
  const std::string expected = "ack_time_mac: expected unsigned 32-bit integer";
  for (const char* text : {"4294967296", "18446744073709551616", "-1", "1.0", "1e3"}) {
    SCOPED_TRACE(text);
    EXPECT_TRUE(fails_with(decode_control_message(set_member(sample_control_text(), "ack_time_mac", text)),
                           PeerError::out_of_range, expected + ", got " + text));
  }
  EXPECT_TRUE(fails_with(decode_control_message(set_member(sample_control_text(), "ack_time_mac", "[]")),
                         PeerError::wrong_type, expected));
  EXPECT_TRUE(fails_with(decode_control_message(remove_member(sample_control_text(), "ack_time_mac")),
                         PeerError::missing_field, "ack_time_mac: required field missing"));
}

TEST(JsonCodecControl, ClientUserDataIsOptionalAndNullMeansAbsent) {
  auto decoded = decode_control_message(remove_member(sample_control_text(), "client_user_data"));
  ASSERT_TRUE(decoded.ok());
  EXPECT_FALSE(decoded->client_user_data.has_value());
  decoded = decode_control_message(set_member(sample_control_text(), "client_user_data", "null"));
  ASSERT_TRUE(decoded.ok());
  EXPECT_FALSE(decoded->client_user_data.has_value());

  OcpControlMessage message = sample_control();
  message.client_user_data.reset();
  std::string text;
  encode_control_message(message, text);
  EXPECT_EQ(text.find("client_user_data"), std::string::npos);
}

TEST(JsonCodecControl, ClientUserDataIsCarriedByteExactWithBigIntegers) {
  const std::string user_data =
      R"({ "id": 18446744073709551617, "big": 123456789012345678901234567890,)"
      R"( "f": 1.50, "s": "\u00e9\n", "a": [1, {"b": null}] })";
  const auto decoded =
      decode_control_message(set_member(sample_control_text(), "client_user_data", user_data));
  ASSERT_TRUE(decoded.ok()) << decoded.error().message();
  EXPECT_EQ(decoded->client_user_data->text, user_data);
  std::string encoded;
  encode_control_message(*decoded, encoded);
  EXPECT_NE(encoded.find(user_data), std::string::npos);
}

TEST(JsonCodecControl, ClientUserDataMayBeAnyJsonValue) {
  for (const char* value :
       {"\"text\"", R"("q\"\\")", "[1,2]", "7", "-1.5e3", "true", "false", R"({"a":{}})"}) {
    const auto decoded =
        decode_control_message(set_member(sample_control_text(), "client_user_data", value));
    ASSERT_TRUE(decoded.ok());
    EXPECT_EQ(decoded->client_user_data->text, value);
  }
}

TEST(JsonCodecControl, UnknownFieldsAreIgnoredEverywhere) {
  std::string text = sample_control_text();
  text = test::replace_once(text, "{\"controller\":", R"({"future":{"x":[1,{"y":2}]},"controller":)");
  text = test::replace_once(text, "{\"a\":", R"({"turbo":true,"a":)");
  text = test::replace_once(text, "{\"left_x\":", R"({"z_axis":"?","left_x":)");
  text = test::replace_once(text, "{\"latency\":", R"({"jitter":[],"latency":)");
  text = test::replace_once(text, "\"ack_time\":", R"("ack_time_extra":-1.5e3,"ack_time":)");
  const auto decoded = decode_control_message(text);
  ASSERT_TRUE(decoded.ok()) << decoded.error().message();
  EXPECT_EQ(*decoded, sample_control());
}

TEST(JsonCodecControl, DuplicateKeysAreAllValidatedAndTheLastOneWins) {
  std::string text = sample_control_text();
  text.insert(text.size() - 1, R"(,"ack_time":7)");
  auto decoded = decode_control_message(text);
  ASSERT_TRUE(decoded.ok());
  EXPECT_EQ(decoded->ack.ack_time, 7u);

  text = sample_control_text();
  text.insert(text.size() - 1, R"(,"ack_time":"late")");
  EXPECT_TRUE(fails_with(decode_control_message(text), PeerError::wrong_type,
                         "ack_time: expected unsigned 64-bit integer"));
}

TEST(JsonCodecControl, EncodeControllerWritesTheControllerObjectAlone) {
  std::string text;
  encode_controller(Controller::safe_default(), text);
  EXPECT_EQ(text.front(), '{');
  EXPECT_NE(text.find(R"("left_trigger":-1.0)"), std::string::npos);
  const auto wrapped = decode_control_message(set_member(sample_control_text(), "controller", text));
  ASSERT_TRUE(wrapped.ok());
  EXPECT_TRUE(wrapped->controller->is_safe_default());
}

}  // namespace
}  // namespace ocp
