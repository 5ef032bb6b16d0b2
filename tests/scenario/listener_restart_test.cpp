// A restart of the Streamer's vehicle listener (disconnect with listener_down, issue #34): the
// Streamer closes the connection and refuses new ones that long, so the in-process client is
// back only after the port is. Exact in virtual time; the real-time half (an external client's
// TcpServer stopped and listening again on the same port) is in tests/campaign/client_test.sh.
#include "scenario/write.hpp"
#include "scenario_test_support.hpp"

namespace ocp::scenario {
namespace {

using test::only;
using test::run_text;

std::string restart_world(const std::string& cleared_within) {
  return R"(seed: 4
duration: 4s
world:
  reconnect_backoff: 100ms
  vehicles:
    - name: truck-1
timeline:
  - {at: 1s, name: restart, disconnect: {vehicle: truck-1, listener_down: 750ms}}
expect:
  faults:
    - fault: VehicleNoResponse
      raised: {after: restart, within: 10ms}
      cleared: {after: restart, within: )" + cleared_within + R"(}
)";
}

TEST(ListenerRestart, TheClientIsBackOnlyAfterThePortIs) {
  // Refused at 100, 200, … 700 ms; the try at 800 ms is the first after the port is back.
  const auto outcome = run_text(restart_world("[800ms, 810ms]"));
  ASSERT_EQ(outcome.verdicts.size(), 2u);
  for (const auto& verdict : outcome.verdicts) EXPECT_TRUE(verdict.passed) << verdict.title << ": " << verdict.actual;
}

TEST(ListenerRestart, AReconnectWhileThePortIsClosedWouldFail) {
  // The plain disconnect's window: back after one backoff. A restart must not meet it.
  const auto outcome = run_text(restart_world("[100ms, 150ms]"));
  ASSERT_EQ(outcome.verdicts.size(), 2u);
  EXPECT_FALSE(outcome.verdicts[1].passed) << outcome.verdicts[1].actual;
}

TEST(ListenerRestart, WritesBackAndRefusesABadLength) {
  const std::string yaml = restart_world("[800ms, 810ms]");
  const std::string written = write_scenario_yaml(parse_scenario(yaml, "restart.yaml"));
  EXPECT_NE(written.find("listener_down: 750ms"), std::string::npos) << written;
  EXPECT_EQ(write_scenario_yaml(parse_scenario(written, "written.yaml")), written);
  for (const char* bad : {"0ms", "-1s", "61s"}) {
    std::string broken = yaml;
    broken.replace(broken.find("750ms"), 5, bad);
    EXPECT_THROW(parse_scenario(broken, "bad.yaml"), ScenarioError) << bad;
  }
}

}  // namespace
}  // namespace ocp::scenario
