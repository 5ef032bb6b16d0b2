// Hostile and malformed input: every decoder returns an error value, never throws or aborts.
#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "json_codec_test_support.hpp"
#include "ocp/json_codec.hpp"

namespace ocp {
namespace {

using test::fails_with;
using test::fails_with_code;

// Runs all four decoders on `json` and checks each fails with `code`.
::testing::AssertionResult all_fail_with(const std::string& json, PeerError code) {
  const ::testing::AssertionResult results[] = {
      fails_with_code(decode_control_message(json), code),
      fails_with_code(decode_vehicle_response(json), code),
      fails_with_code(decode_vehicle_ocp_shared(json), code),
      fails_with_code(decode_client_ocp_shared(json), code),
  };
  for (const auto& result : results) {
    if (!result) return result;
  }
  return ::testing::AssertionSuccess();
}

// Decodes with all four decoders; whatever the outcome, errors must carry a detail.
void decode_everything(const std::string& json) {
  const auto check = [](const auto& result) {
    if (!result.ok()) {
      EXPECT_FALSE(result.error().detail.empty());
    }
  };
  check(decode_control_message(json));
  check(decode_vehicle_response(json));
  check(decode_vehicle_ocp_shared(json));
  check(decode_client_ocp_shared(json));
}

std::string control_seed() { return test::read_data_file("seeds/000_control_message.json"); }

TEST(JsonCodecHostile, TopLevelNonObjectsAreNotAnObject) {
  for (const char* json : {"null", "[]", "[{}]", "42", "\"text\"", "true", " 1.5 "}) {
    SCOPED_TRACE(json);
    EXPECT_TRUE(all_fail_with(json, PeerError::not_an_object));
  }
  EXPECT_TRUE(fails_with(decode_vehicle_response("[]"), PeerError::not_an_object,
                         "top-level value is not an object"));
}

TEST(JsonCodecHostile, SyntaxErrorsAreMalformed) {
  for (const char* json : {"", " ", "{", "}", "{\"a\":}", "{\"a\" 1}", "{a:1}", "{'a':1}",
                           "{\"a\":1,}", "{\"a\":01}", "{\"a\":1.}", "{\"a\":-}", "{} {}",
                           "{}x", "{\"a\":tru}", "{\"a\":\"\\x\"}", "{/*c*/}", "{\"a\":\"\t\"}"}) {
    SCOPED_TRACE(json);
    EXPECT_TRUE(all_fail_with(json, PeerError::malformed_json));
  }
}

// A zero-length frame reaches the decoders as a default-constructed view (null data pointer).
TEST(JsonCodecHostile, EmptyViewWithNullDataIsMalformed) {
  const std::string_view empty;
  EXPECT_TRUE(fails_with_code(decode_control_message(empty), PeerError::malformed_json));
  EXPECT_TRUE(fails_with_code(decode_vehicle_response(empty), PeerError::malformed_json));
  EXPECT_TRUE(fails_with_code(decode_vehicle_ocp_shared(empty), PeerError::malformed_json));
  EXPECT_TRUE(fails_with_code(decode_client_ocp_shared(empty), PeerError::malformed_json));
}

TEST(JsonCodecHostile, NanAndInfinityLiteralsAreMalformed) {
  for (const char* literal : {"NaN", "Infinity", "-Infinity", "nan", "inf"}) {
    SCOPED_TRACE(literal);
    EXPECT_TRUE(all_fail_with(std::string("{\"ack_time\":") + literal + "}",
                              PeerError::malformed_json));
    EXPECT_TRUE(fails_with_code(
        decode_control_message(test::replace_once(control_seed(), "0.0", literal)),
        PeerError::malformed_json));
  }
}

TEST(JsonCodecHostile, NumbersBeyondDoubleRangeAreMalformed) {
  // RapidJSON refuses numbers whose magnitude exceeds a double, even inside user data.
  EXPECT_TRUE(fails_with_code(
      decode_control_message(test::replace_once(control_seed(), "\"manual\"", "1e400")),
      PeerError::malformed_json));
}

TEST(JsonCodecHostile, InvalidUtf8IsMalformedEverywhere) {
  const std::string bad_sequences[] = {"\xff", "\xc0\xaf", "\xed\xa0\x80", "\xe2\x82",
                                       "\xf4\x90\x80\x80", "\x80"};
  for (const std::string& bad : bad_sequences) {
    // In a field value, in user data, in an unknown key.
    EXPECT_TRUE(fails_with_code(
        decode_control_message(test::replace_once(control_seed(), "\"fault_reason\": \"",
                                                  "\"fault_reason\": \"" + bad)),
        PeerError::malformed_json));
    EXPECT_TRUE(fails_with_code(
        decode_control_message(test::replace_once(control_seed(), "manual", "man" + bad)),
        PeerError::malformed_json));
    EXPECT_TRUE(all_fail_with("{\"k" + bad + "\":1}", PeerError::malformed_json));
  }
  // A lone surrogate escape is not a character either.
  EXPECT_TRUE(all_fail_with(R"({"k":"\ud800"})", PeerError::malformed_json));
  EXPECT_TRUE(all_fail_with(R"({"k":"a\udc00"})", PeerError::malformed_json));
  EXPECT_TRUE(all_fail_with(R"({"\udfff":1})", PeerError::malformed_json));
  // A proper pair is fine, and so is U+D7FF / U+E000 right next to the surrogate range.
  const auto pair = decode_client_ocp_shared(R"({"active_vehicle":"\ud83d\ude97\ud7ff\ue000"})");
  ASSERT_TRUE(pair.ok()) << pair.error().message();
  EXPECT_EQ(*pair->active_vehicle, "\xf0\x9f\x9a\x97\xed\x9f\xbf\xee\x80\x80");
}

TEST(JsonCodecHostile, ValidMultibyteUtf8IsAccepted) {
  const auto decoded = decode_control_message(
      test::replace_once(control_seed(), "\"fault_reason\": \"\"",
                         "\"fault_reason\": \"K\xc3\xa4mera \xe2\x82\xac \xf0\x9f\x9a\x97\""));
  ASSERT_TRUE(decoded.ok()) << decoded.error().message();
  EXPECT_EQ(decoded->telemetry.fault_reason, "K\xc3\xa4mera \xe2\x82\xac \xf0\x9f\x9a\x97");
}

TEST(JsonCodecHostile, EmbeddedNulBytesAreMalformed) {
  std::string json = control_seed();
  json.push_back('\0');
  json += "{}";
  EXPECT_TRUE(fails_with_code(decode_control_message(json), PeerError::malformed_json));
  std::string in_string = test::replace_once(control_seed(), "manual", std::string("ma\0nual", 7));
  EXPECT_TRUE(fails_with_code(decode_control_message(in_string), PeerError::malformed_json));
}

TEST(JsonCodecHostile, DeepNestingIsTooDeep) {
  EXPECT_TRUE(all_fail_with(std::string(100000, '['), PeerError::too_deep));
  EXPECT_TRUE(all_fail_with("{\"x\":" + std::string(100000, '['), PeerError::too_deep));
  std::string objects;
  for (int i = 0; i < 100000; ++i) objects += "{\"a\":";
  EXPECT_TRUE(all_fail_with(objects, PeerError::too_deep));
}

TEST(JsonCodecHostile, DepthLimitCountsFromTheTopLevelObject) {
  // The message object is level 1, client_user_data level 2: user data may nest 63 deeper.
  const auto with_user_data_depth = [](int depth) {
    const std::string user_data = std::string(static_cast<std::size_t>(depth - 1), '[') + "{}" +
                                  std::string(static_cast<std::size_t>(depth - 1), ']');
    return test::replace_once(
        test::read_data_file("seeds/000_control_message.json"),
        "{\n    \"mode\": \"manual\"\n  }", user_data);
  };
  EXPECT_TRUE(decode_control_message(with_user_data_depth(max_json_depth - 1)).ok());
  EXPECT_TRUE(fails_with_code(decode_control_message(with_user_data_depth(max_json_depth)),
                              PeerError::too_deep));
}

TEST(JsonCodecHostile, HugeStringsAreHandled) {
  const std::string huge(1 << 20, 'x');
  auto decoded = decode_control_message(
      test::replace_once(control_seed(), "\"fault_reason\": \"\"", "\"fault_reason\": \"" + huge + "\""));
  ASSERT_TRUE(decoded.ok());
  EXPECT_EQ(decoded->telemetry.fault_reason.size(), huge.size());
  decoded = decode_control_message(
      test::replace_once(control_seed(), "{", "{\"junk\":\"" + huge + "\","));
  EXPECT_TRUE(decoded.ok());
  EXPECT_TRUE(fails_with_code(decode_control_message("{\"a\":\"" + huge),
                              PeerError::malformed_json));
}

TEST(JsonCodecHostile, HugeNumbersInTypedFieldsAreOutOfRangeWithAShortDetail) {
  const std::string digits(5000, '9');
  const auto result = decode_vehicle_response("{\"ack_time\":" + digits + ",\"ack_time_mac\":1}");
  ASSERT_FALSE(result.ok());
  EXPECT_LT(result.error().detail.size(), 120u) << "peer text is truncated in the detail";
}

TEST(JsonCodecHostile, EveryPrefixOfASeedFailsCleanly) {
  const std::string json = control_seed();
  const std::size_t closing_brace = json.rfind('}');
  for (std::size_t length = 0; length <= closing_brace; ++length) {
    const std::string prefix = json.substr(0, length);
    const auto result = decode_control_message(prefix);
    EXPECT_FALSE(result.ok()) << length;
  }
}

TEST(JsonCodecHostile, RandomMutationsNeverCrash) {
  std::mt19937 generator(20261122);
  const std::vector<std::string> seeds = {
      control_seed(), test::read_data_file("seeds/000_response_with_vehicle_data.json"),
      test::read_data_file("seeds/004_vehicle_feedback.derived.json"),
      test::read_data_file("seeds/003_client_user_data_webview.derived.json")};
  const char interesting[] = "{}[]\",:0-1.eE\\u\xff\x00 ntf";
  for (int round = 0; round < 4000; ++round) {
    std::string json = seeds[static_cast<std::size_t>(round) % seeds.size()];
    const int edits = 1 + static_cast<int>(generator() % 4);
    for (int edit = 0; edit < edits && !json.empty(); ++edit) {
      const std::size_t at = generator() % json.size();
      const char c = interesting[generator() % (sizeof interesting - 1)];
      switch (generator() % 3) {
        case 0: json[at] = c; break;
        case 1: json.insert(at, 1, c); break;
        default: json.erase(at, 1 + generator() % 8); break;
      }
    }
    decode_everything(json);
  }
}

TEST(JsonCodecHostile, SeedSchemasAreValidJsonButNotMessages) {
  for (const char* file : {"seeds/001_control_schema.json", "seeds/001_response_schema.json"}) {
    const std::string schema = test::read_data_file(file);
    EXPECT_TRUE(validate_raw_json(schema).ok()) << file;
    EXPECT_TRUE(fails_with_code(decode_control_message(schema), PeerError::missing_field));
    EXPECT_TRUE(fails_with_code(decode_vehicle_response(schema), PeerError::missing_field));
  }
}

TEST(JsonCodecHostile, ValidateRawJsonAcceptsExactlyOneValue) {
  for (const char* json : {"null", "1", "\"s\"", "[1,{\"a\":[]}]", " {} ", "18446744073709551617"}) {
    EXPECT_TRUE(validate_raw_json(json).ok()) << json;
  }
  for (const char* json : {"", "1 2", "{", "[1,]", "NaN", "\"\xff\""}) {
    const Status status = validate_raw_json(json);
    ASSERT_FALSE(status.ok()) << json;
    EXPECT_EQ(status.error().code, make_error_code(PeerError::malformed_json)) << json;
  }
  EXPECT_EQ(validate_raw_json(std::string(1000, '[')).error().code,
            make_error_code(PeerError::too_deep));
}

TEST(JsonCodecHostile, EncoderEscapesStringsAndReplacesInvalidUtf8) {
  OcpControlMessage message;
  message.telemetry.fault_reason = "q\"b\\n\n\t\x01\x1f \xc3\xa4 \xff end";
  std::string text;
  encode_control_message(message, text);
  EXPECT_NE(text.find(R"("q\"b\\n\n\t\u0001\u001f )"), std::string::npos) << text;
  EXPECT_NE(text.find("\\ufffd end"), std::string::npos) << text;
  const auto decoded = decode_control_message(text);
  ASSERT_TRUE(decoded.ok()) << decoded.error().message();
  EXPECT_EQ(decoded->telemetry.fault_reason, "q\"b\\n\n\t\x01\x1f \xc3\xa4 \xef\xbf\xbd end");
}

TEST(JsonCodecHostile, EncoderWritesNonFiniteDoublesAsNull) {
  OcpControlMessage message;
  message.controller = Controller::safe_default();
  message.controller->axes.left_x = std::numeric_limits<double>::quiet_NaN();
  message.controller->axes.left_y = std::numeric_limits<double>::infinity();
  std::string text;
  encode_control_message(message, text);
  EXPECT_NE(text.find(R"("left_x":null,"left_y":null)"), std::string::npos) << text;
  EXPECT_TRUE(validate_raw_json(text).ok()) << "output stays valid JSON";
  EXPECT_TRUE(fails_with(decode_control_message(text), PeerError::wrong_type,
                         "controller.axes.left_x: expected number"));
}

}  // namespace
}  // namespace ocp
