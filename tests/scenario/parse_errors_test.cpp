// Every kind of mistake in a scenario file is an error naming the file, the line and column
// of the offending node, and why.
#include "scenario_test_support.hpp"

namespace ocp::scenario {
namespace {

struct BadFile {
  const char* what;
  std::string yaml;
  int line;
  const char* reason;   // a substring of the reason
};

void PrintTo(const BadFile& bad, std::ostream* out) { *out << bad.what; }

const std::string head = "seed: 1\nduration: 10s\nworld:\n  vehicles:\n    - name: truck-1\n";   // lines 1-5

class ParseErrors : public ::testing::TestWithParam<BadFile> {};

TEST_P(ParseErrors, NameFileLineAndReason) {
  const BadFile& bad = GetParam();
  try {
    parse_scenario(bad.yaml, "bad/file.yaml");
    FAIL() << bad.what << ": no error";
  } catch (const ScenarioError& error) {
    EXPECT_EQ(error.file(), "bad/file.yaml");
    EXPECT_EQ(error.line(), bad.line) << error.what();
    EXPECT_NE(error.reason().find(bad.reason), std::string::npos) << error.what();
    EXPECT_EQ(std::string(error.what()).rfind("bad/file.yaml:" + std::to_string(bad.line) + ":", 0), 0u) << error.what();
  }
}

INSTANTIATE_TEST_SUITE_P(
    Kinds, ParseErrors,
    ::testing::Values(
        BadFile{"unknown top-level key", head + "expect: {invariants: [no_stale_pair_after_reconnect]}\ncolour: red\n", 7, "unknown key 'colour'"},
        BadFile{"unknown vehicle key", head + "      latency_limt: 300ms\nexpect: {invariants: [no_stale_pair_after_reconnect]}\n", 6, "unknown key 'latency_limt'"},
        BadFile{"bad duration", head + "      latency_limit: 300\nexpect: {invariants: [no_stale_pair_after_reconnect]}\n", 6, "needs a unit"},
        BadFile{"bad probability", head + "      link: {loss: 1.5}\nexpect: {invariants: [no_stale_pair_after_reconnect]}\n", 6, "out of range"},
        BadFile{"events out of order", head + "timeline:\n  - {at: 5s, gamepad: unplug}\n  - {at: 2s, gamepad: replug}\nexpect: {invariants: [no_stale_pair_after_reconnect]}\n", 8, "before the previous one"},
        BadFile{"event after the end", head + "timeline:\n  - {at: 50s, gamepad: unplug}\nexpect: {invariants: [no_stale_pair_after_reconnect]}\n", 7, "after the end"},
        BadFile{"unknown vehicle in an action", head + "timeline:\n  - {at: 1s, disconnect: {vehicle: truck-9}}\nexpect: {invariants: [no_stale_pair_after_reconnect]}\n", 7, "unknown vehicle 'truck-9'"},
        BadFile{"expectation names no event", head + "expect:\n  faults:\n    - {fault: InputLost, raised: {after: nowhere, within: 1s}}\n", 8, "names no timeline event"},
        BadFile{"unknown fault", head + "expect:\n  faults:\n    - {fault: TooHot, never: true}\n", 8, "unknown fault 'TooHot'"},
        BadFile{"unknown metric", head + "expect:\n  thresholds:\n    latency_us: [\"max < 5\"]\n", 8, "unknown metric"},
        BadFile{"bad threshold", head + "expect:\n  thresholds:\n    latency_ms: [\"p(99) less 5\"]\n", 8, "unknown operator"},
        BadFile{"unknown invariant", head + "expect:\n  invariants: [always_safe]\n", 7, "unknown invariant"},
        BadFile{"no expectation", head + "expect: {}\n", 6, "no expectation"},
        BadFile{"missing duration", "seed: 1\nworld:\n  vehicles: [{name: a}]\nexpect: {invariants: [no_stale_pair_after_reconnect]}\n", 1, "missing required key 'duration'"},
        BadFile{"YAML syntax", head + "expect: [\n", 7, ""},
        BadFile{"non-scalar key", head + "      [x, y]: 3\nexpect: {invariants: [no_stale_pair_after_reconnect]}\n", 6, "bad conversion"},
        BadFile{"two actions in one event", head + "timeline:\n  - {at: 1s, gamepad: unplug, disconnect: {}}\nexpect: {invariants: [no_stale_pair_after_reconnect]}\n", 7, "exactly one action"}),
    [](const ::testing::TestParamInfo<BadFile>& info) {
      std::string name = info.param.what;
      for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
      return name;
    });

TEST(ParseDurations, Units) {
  EXPECT_EQ(parse_duration_text("12.5s"), Micros{12'500'000});
  EXPECT_EQ(parse_duration_text("350ms"), Micros{350'000});
  EXPECT_EQ(parse_duration_text("250us"), Micros{250});
  EXPECT_EQ(parse_duration_text("2min"), Micros{120'000'000});
  EXPECT_THROW(parse_duration_text("5 parsecs"), std::invalid_argument);
}

}  // namespace
}  // namespace ocp::scenario
