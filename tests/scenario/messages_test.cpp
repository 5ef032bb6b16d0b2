// Scenario file messages a new user meets (issue #20 item 9): misspelt names get "did you
// mean", a mis-indented line says which line and what YAML expected, `h` is a unit.
#include "scenario_test_support.hpp"

namespace ocp::scenario {
namespace {

struct Message {
  const char* what;
  std::string yaml;
  int line;
  std::vector<std::string> fragments;   // each must appear in the error
};

void PrintTo(const Message& message, std::ostream* out) { *out << message.what; }

const std::string file_head = "seed: 1\nduration: 10s\nworld:\n  vehicles:\n    - name: truck-1\n";   // lines 1-5
const std::string some_expectation = "expect: {invariants: [no_stale_pair_after_reconnect]}\n";

class ScenarioMessages : public ::testing::TestWithParam<Message> {};

TEST_P(ScenarioMessages, SayWhereAndWhat) {
  const Message& message = GetParam();
  try {
    parse_scenario(message.yaml, "my.yaml");
    FAIL() << message.what << ": no error";
  } catch (const ScenarioError& error) {
    const std::string text = error.what();
    EXPECT_EQ(error.line(), message.line) << text;
    EXPECT_EQ(text.rfind("my.yaml:" + std::to_string(message.line) + ":", 0), 0u) << text;
    for (const std::string& fragment : message.fragments) EXPECT_NE(text.find(fragment), std::string::npos) << text;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Table, ScenarioMessages,
    ::testing::Values(
        // did you mean: one rule for keys, faults, actions, names.
        Message{"misspelt key", file_head + "      latency_limt: 300ms\n" + some_expectation, 6,
                {"unknown key 'latency_limt' in vehicle: did you mean 'latency_limit'?"}},
        Message{"misspelt top-level key", file_head + "expcet: {invariants: [no_stale_pair_after_reconnect]}\n", 6,
                {"unknown key 'expcet' in scenario: did you mean 'expect'?"}},
        Message{"misspelt action", file_head + "timeline:\n  - {at: 1s, outgae: {for: 1s}}\n" + some_expectation, 7,
                {"unknown key 'outgae' in timeline event: did you mean 'outage'?"}},
        Message{"misspelt fault", file_head + "expect:\n  faults:\n    - {fault: HighLatncy, never: true}\n", 8,
                {"unknown fault 'HighLatncy': did you mean 'HighLatency'?"}},
        Message{"fault in the wrong case", file_head + "expect:\n  faults:\n    - {fault: invalidmac, never: true}\n", 8,
                {"did you mean 'InvalidMac'?"}},
        Message{"unknown fault, nothing close", file_head + "expect:\n  faults:\n    - {fault: TooHot, never: true}\n", 8,
                {"unknown fault 'TooHot' (known: VehicleNoResponse, ", "VehicleControlInactive)"}},
        Message{"misspelt vehicle", file_head + "timeline:\n  - {at: 1s, disconnect: {vehicle: truck-l}}\n" + some_expectation, 7,
                {"unknown vehicle 'truck-l': did you mean 'truck-1'?"}},
        Message{"misspelt event name",
                file_head + "timeline:\n  - {at: 1s, name: ramp_up, gamepad: unplug}\nexpect:\n  faults:\n"
                       "    - {fault: InputLost, raised: {after: rampup, within: 1s}}\n",
                10, {"'rampup' names no timeline event (and is not a time): did you mean 'ramp_up'?"}},
        Message{"misspelt invariant", file_head + "expect: {invariants: [no_stale_pair_after_reconect]}\n", 6,
                {"unknown invariant 'no_stale_pair_after_reconect': did you mean 'no_stale_pair_after_reconnect'?"}},
        Message{"misspelt metric", file_head + "expect:\n  thresholds:\n    latncy_ms: [\"max < 5\"]\n", 8,
                {"unknown metric 'latncy_ms': did you mean 'latency_ms'?"}},
        Message{"misspelt aggregate", file_head + "expect:\n  thresholds:\n    latency_ms: [\"mxa < 5\"]\n", 8,
                {"unknown aggregate 'mxa': did you mean 'max'?"}},
        Message{"misspelt gamepad action", file_head + "timeline:\n  - {at: 1s, gamepad: unplg}\n" + some_expectation, 7,
                {"unknown gamepad action 'unplg': did you mean 'unplug'?"}},
        Message{"misspelt direction", file_head + "timeline:\n  - {at: 1s, outage: {direction: to_streamr, for: 1s}}\n" + some_expectation, 7,
                {"unknown direction 'to_streamr': did you mean 'to_streamer'?"}},
        Message{"misspelt misbehaviour", file_head + "      misbehave: {corupt_mac: true}\n" + some_expectation, 6,
                {"unknown key 'corupt_mac' in misbehave: did you mean 'corrupt_mac'?"}},
        Message{"misspelt camera", file_head + "      cameras: [{name: front}]\ntimeline:\n  - {at: 1s, camera_stall: {camera: frnot}}\n" + some_expectation, 8,
                {"unknown camera 'frnot' in vehicle 'truck-1': did you mean 'front'?"}},
        // The unit list names h.
        Message{"duration without a unit", file_head + "      latency_limit: 300\n" + some_expectation, 6,
                {"needs a unit: us, ms, s, min or h"}},
        // A mis-indented line: its number, what YAML expected there, and the line itself.
        Message{"list entry indented one space short", file_head + "     link: {delay: 20ms}\n" + some_expectation, 6,
                {"YAML expected another list item", "check this line's indentation", "line 6 is \"     link: {delay: 20ms}\"",
                 "(YAML: end of sequence not found)"}},
        Message{"top-level key indented", file_head + "   expect: {}\n", 6,
                {"YAML expected another 'key: value' at the mapping's indentation", "line 6 is \"   expect: {}\""}},
        Message{"key indented deeper than the one before", "seed: 1\n  duration: 10s\n", 2,
                {"YAML did not expect 'key: value' here", "line 2 is \"  duration: 10s\""}},
        Message{"unclosed list", file_head + "expect: [\n", 7, {"YAML expected ']' to close a '[' list"}}),
    [](const ::testing::TestParamInfo<Message>& info) {
      std::string name = info.param.what;
      for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
      return name;
    });

TEST(ScenarioFileMessages, HoursAreAUnit) {
  EXPECT_EQ(parse_duration_text("1h"), Micros{3'600'000'000});
  EXPECT_EQ(parse_duration_text("1.5h"), Micros{5'400'000'000});
  const Scenario scenario = parse_scenario("duration: 2h\nworld: {vehicles: [{name: a}]}\n" + some_expectation, "long.yaml");
  EXPECT_EQ(scenario.duration, Micros{7'200'000'000});
}

TEST(ScenarioFileMessages, AMissingFileGivesTheSystemError) {
  try {
    load_scenario("/nonexistent/foo.yaml");
    FAIL() << "no error";
  } catch (const ScenarioError& error) {
    EXPECT_STREQ(error.what(), "/nonexistent/foo.yaml: cannot open the scenario file: No such file or directory");
  }
}

}  // namespace
}  // namespace ocp::scenario
