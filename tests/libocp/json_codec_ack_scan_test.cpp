// scan_control_ack_pair: the vehicle client's echo path reads the pair without decoding the
// message. It must find the pair the decoder finds, or nothing (never a different one).
#include <gtest/gtest.h>

#include <optional>
#include <string>

#include "ocp/json_codec.hpp"

namespace ocp {
namespace {

constexpr const char* telemetry = R"("telemetry":{"latency":0,"fault":false,"fault_reason":""})";

std::string message(const std::string& members) { return std::string("{") + telemetry + "," + members + "}"; }

struct ScanCase {
  const char* name;
  std::string json;
  std::optional<AckPair> expected;   // nullopt: the scan leaves it to the decoder
};

void PrintTo(const ScanCase& scan_case, std::ostream* out) { *out << scan_case.name; }

class AckScan : public ::testing::TestWithParam<ScanCase> {};

TEST_P(AckScan, FindsWhatTheDecoderFindsOrNothing) {
  const ScanCase& scan_case = GetParam();
  const std::optional<AckPair> scanned = scan_control_ack_pair(scan_case.json);
  EXPECT_EQ(scanned.has_value(), scan_case.expected.has_value()) << scan_case.json;
  if (scanned && scan_case.expected) {
    EXPECT_EQ(*scanned, *scan_case.expected) << scan_case.json;
  }
  const Result<OcpControlMessage> decoded = decode_control_message(scan_case.json);
  if (scanned && decoded.ok()) {
    EXPECT_EQ(*scanned, decoded->ack) << scan_case.json;
  }
}

const std::uint64_t u64_max = ~std::uint64_t{0};

INSTANTIATE_TEST_SUITE_P(
    Table, AckScan,
    ::testing::Values(
        ScanCase{"plain", message(R"("ack_time":123456,"ack_time_mac":987654321)"), AckPair{123456, 987654321}},
        ScanCase{"pair_first", std::string(R"({"ack_time_mac":7,"ack_time":8,)") + telemetry + "}", AckPair{8, 7}},
        ScanCase{"whitespace", " {\n \"ack_time\" : 5 ,\t\"ack_time_mac\"\r:\n6 , " + std::string(telemetry) + " } ",
                 AckPair{5, 6}},
        ScanCase{"extremes", message(R"("ack_time":18446744073709551615,"ack_time_mac":4294967295)"),
                 AckPair{u64_max, 4294967295U}},
        ScanCase{"zero", message(R"("ack_time":0,"ack_time_mac":0)"), AckPair{0, 0}},
        ScanCase{"duplicate_keys_last_wins", message(R"("ack_time":1,"ack_time_mac":2,"ack_time":3)"), AckPair{3, 2}},
        ScanCase{"pair_inside_user_data_is_not_the_pair",
                 message(R"("client_user_data":{"ack_time":1,"ack_time_mac":1},"ack_time":9,"ack_time_mac":10)"),
                 AckPair{9, 10}},
        ScanCase{"key_text_inside_a_string",
                 message(R"("client_user_data":"\",\"ack_time\":1,\"x\":\"","ack_time":9,"ack_time_mac":10)"),
                 AckPair{9, 10}},
        ScanCase{"nested_arrays_and_strings",
                 message(R"("controller":null,"client_user_data":[[{"a":"]}"}],"}"],"ack_time":4,"ack_time_mac":4)"),
                 AckPair{4, 4}},
        ScanCase{"escaped_key", message(R"("ack\u005ftime":1,"ack_time_mac":2)"), std::nullopt},
        ScanCase{"missing_mac", message(R"("ack_time":1)"), std::nullopt},
        ScanCase{"missing_time", message(R"("ack_time_mac":1)"), std::nullopt},
        ScanCase{"fraction", message(R"("ack_time":1.0,"ack_time_mac":2)"), std::nullopt},
        ScanCase{"exponent", message(R"("ack_time":1e3,"ack_time_mac":2)"), std::nullopt},
        ScanCase{"negative", message(R"("ack_time":-1,"ack_time_mac":2)"), std::nullopt},
        ScanCase{"leading_zero", message(R"("ack_time":01,"ack_time_mac":2)"), std::nullopt},
        ScanCase{"u64_overflow", message(R"("ack_time":18446744073709551616,"ack_time_mac":2)"), std::nullopt},
        ScanCase{"mac_over_u32", message(R"("ack_time":1,"ack_time_mac":4294967296)"), std::nullopt},
        ScanCase{"string_pair", message(R"("ack_time":"1","ack_time_mac":2)"), std::nullopt},
        ScanCase{"not_an_object", R"([{"ack_time":1,"ack_time_mac":2}])", std::nullopt},
        ScanCase{"truncated", R"({"ack_time":1,"ack_time_mac":2)", std::nullopt},
        ScanCase{"empty", "", std::nullopt},
        ScanCase{"empty_object", "{}", std::nullopt}));

TEST(AckScan, FindsThePairInEveryMessageTheEncoderWrites) {
  OcpControlMessage message;
  message.controller = Controller::safe_default();
  message.telemetry.fault_reason = "High Latency, \"quoted\" \\ reason";
  message.telemetry.missing_cameras = {"front", "}{]["};
  message.client_user_data = RawJson{R"({"ack_time":1,"nested":[{"ack_time_mac":2}]})"};
  for (const AckPair pair : {AckPair{0, 0}, AckPair{(1ULL << 53) + 1, 1}, AckPair{u64_max, 4294967295U}}) {
    message.ack = pair;
    std::string json;
    encode_control_message(message, json);
    EXPECT_EQ(scan_control_ack_pair(json), pair) << json;
  }
}

}  // namespace
}  // namespace ocp
