// ControlMessageDecoder: decode_control_message in two steps, the vehicle client's echo path.
// start() gives the pair as the full decode reads it (or none); finish() gives exactly what
// decode_control_message gives, whatever the input.
#include <gtest/gtest.h>

#include <optional>
#include <string>

#include "ocp/json_codec.hpp"

namespace ocp {
namespace {

constexpr const char* telemetry = R"("telemetry":{"latency":0,"fault":false,"fault_reason":""})";

std::string message(const std::string& members) { return std::string("{") + telemetry + "," + members + "}"; }

struct TwoStepCase {
  const char* name;
  std::string json;
  std::optional<AckPair> pair;   // what start() gives
  bool decodes;                  // whether the message as a whole is valid
};

class ControlTwoStep : public ::testing::TestWithParam<TwoStepCase> {};

TEST_P(ControlTwoStep, GivesThePairFirstAndThenExactlyWhatTheOneStepDecodeGives) {
  const TwoStepCase& two_step = GetParam();
  ControlMessageDecoder decoder;
  EXPECT_EQ(decoder.start(two_step.json), two_step.pair) << two_step.json;
  const Result<OcpControlMessage> finished = decoder.finish();
  const Result<OcpControlMessage> one_step = decode_control_message(two_step.json);
  ASSERT_EQ(finished.ok(), two_step.decodes) << two_step.json;
  ASSERT_EQ(one_step.ok(), two_step.decodes) << two_step.json;
  if (two_step.decodes) {
    EXPECT_EQ(*finished, *one_step);
    EXPECT_EQ(finished->ack, two_step.pair);
  } else {
    EXPECT_EQ(finished.error().message(), one_step.error().message());
  }
}

const std::uint64_t u64_max = ~std::uint64_t{0};

INSTANTIATE_TEST_SUITE_P(
    Table, ControlTwoStep,
    ::testing::Values(
        TwoStepCase{"plain", message(R"("ack_time":123456,"ack_time_mac":987654321)"), AckPair{123456, 987654321}, true},
        TwoStepCase{"pair_first", std::string(R"({"ack_time_mac":7,"ack_time":8,)") + telemetry + "}", AckPair{8, 7}, true},
        TwoStepCase{"extremes", message(R"("ack_time":18446744073709551615,"ack_time_mac":4294967295)"),
                    AckPair{u64_max, 4294967295U}, true},
        TwoStepCase{"duplicate_keys_last_wins", message(R"("ack_time":1,"ack_time_mac":2,"ack_time":3)"), AckPair{3, 2}, true},
        TwoStepCase{"pair_inside_user_data_is_not_the_pair",
                    message(R"("client_user_data":{"ack_time":1,"ack_time_mac":1},"ack_time":9,"ack_time_mac":10)"),
                    AckPair{9, 10}, true},
        TwoStepCase{"key_text_inside_a_string",
                    message(R"("client_user_data":"\",\"ack_time\":1,\"x\":\"","ack_time":9,"ack_time_mac":10)"),
                    AckPair{9, 10}, true},
        TwoStepCase{"escaped_key_is_the_same_key", message(R"("ack\u005ftime":1,"ack_time_mac":2)"), AckPair{1, 2}, true},
        // The pair reads, the message does not: the client has answered it and then closes.
        TwoStepCase{"valid_pair_invalid_message", R"({"ack_time":5,"ack_time_mac":6})", AckPair{5, 6}, false},
        TwoStepCase{"valid_last_pair_invalid_earlier_one", message(R"("ack_time":-1,"ack_time":5,"ack_time_mac":6)"),
                    AckPair{5, 6}, false},
        TwoStepCase{"missing_mac", message(R"("ack_time":1)"), std::nullopt, false},
        TwoStepCase{"missing_time", message(R"("ack_time_mac":1)"), std::nullopt, false},
        TwoStepCase{"fraction", message(R"("ack_time":1.0,"ack_time_mac":2)"), std::nullopt, false},
        TwoStepCase{"negative", message(R"("ack_time":-1,"ack_time_mac":2)"), std::nullopt, false},
        TwoStepCase{"u64_overflow", message(R"("ack_time":18446744073709551616,"ack_time_mac":2)"), std::nullopt, false},
        TwoStepCase{"mac_over_u32", message(R"("ack_time":1,"ack_time_mac":4294967296)"), std::nullopt, false},
        TwoStepCase{"string_pair", message(R"("ack_time":"1","ack_time_mac":2)"), std::nullopt, false},
        TwoStepCase{"not_an_object", R"([{"ack_time":1,"ack_time_mac":2}])", std::nullopt, false},
        TwoStepCase{"truncated", R"({"ack_time":1,"ack_time_mac":2)", std::nullopt, false},
        TwoStepCase{"empty", "", std::nullopt, false}),
    [](const ::testing::TestParamInfo<TwoStepCase>& info) { return std::string(info.param.name); });

TEST(ControlTwoStep, OneDecoderServesMessageAfterMessage) {
  ControlMessageDecoder decoder;
  OcpControlMessage sent;
  sent.controller = Controller::safe_default();
  sent.client_user_data = RawJson{R"({"ack_time":1,"nested":[{"ack_time_mac":2}]})"};
  for (const AckPair pair : {AckPair{0, 0}, AckPair{(1ULL << 53) + 1, 1}, AckPair{u64_max, 4294967295U}}) {
    sent.ack = pair;
    std::string json;
    encode_control_message(sent, json);
    EXPECT_EQ(decoder.start(json), pair) << json;
    const Result<OcpControlMessage> received = decoder.finish();
    ASSERT_TRUE(received.ok()) << json;
    EXPECT_EQ(*received, sent);
  }
  EXPECT_EQ(decoder.start("not json"), std::nullopt);
  EXPECT_FALSE(decoder.finish().ok());
}

}  // namespace
}  // namespace ocp
