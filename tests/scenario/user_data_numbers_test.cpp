// user_data numbers in a scenario file reach the vehicle as written (issue #34): a campaign's
// world.yaml with a u64 above 2^63 once came back as 9223372036854775807, and 1e3 as 1000.0.
#include "scenario_test_support.hpp"

namespace ocp::scenario {
namespace {

std::string user_data_of(const std::string& user_data) {
  const Scenario scenario = parse_scenario(test::one_vehicle("timeline:\n  - {at: 1s, client_data: {source: plugin, vehicles: {truck-1: {user_data: " +
                                                             user_data + "}}}}\nexpect:\n  invariants: [default_controller_during_control_fault]\n"),
                                           "numbers.yaml");
  const auto& data = std::get<ClientDataAction>(scenario.timeline.at(0).action);
  return data.vehicles.at("truck-1").user_data_json.value_or("");
}

TEST(UserDataNumbers, JsonNumbersKeepTheirText) {
  EXPECT_EQ(user_data_of("{max: 18446744073709551615, e: 1e3, neg: -0.125, big: 123456789012345678901234567890}"),
            R"({"max":18446744073709551615,"e":1e3,"neg":-0.125,"big":123456789012345678901234567890})");
}

TEST(UserDataNumbers, WhatIsNotAJsonNumberStaysAsYamlTypesIt) {
  EXPECT_EQ(user_data_of("{quoted: \"42\", word: park, yes: true, none: ~, plus: +5, dot: .5}"),
            R"({"quoted":"42","word":"park","yes":true,"none":null,"plus":5,"dot":0.5})");
}

}  // namespace
}  // namespace ocp::scenario
