// ClientWatch (campaign/client_watch.hpp), the client-facing checks of `ocp_campaign run
// --client`, in virtual time on the in-process reference client: a well-behaved client passes,
// and each check comes out failed for the client that breaks it.
#include <gtest/gtest.h>

#include <string>

#include "campaign/client_watch.hpp"
#include "scenario/parse.hpp"
#include "scenario/runner.hpp"

namespace ocp::campaign {
namespace {

const std::string client_world_head = R"(seed: 5
duration: 4s
world:
  gamepad: drive
  vehicles:
    - name: truck-1
      link: {delay: 10ms}
)";
const std::string client_world_expect = "expect:\n  invariants: [default_controller_during_control_fault]\n";

ClientWatch watched_run(const std::string& vehicle_extra, const std::string& timeline, ClientBounds bounds = {}) {
  const scenario::Scenario world =
      scenario::parse_scenario(client_world_head + vehicle_extra + timeline + client_world_expect, "client_watch.yaml");
  ClientWatch watch(bounds);
  scenario::RunOptions options;
  options.trace = false;
  options.on_built = [&](World& built) { watch.attach(built); };
  options.on_finished = [&](World& built) { watch.finish(built); };
  (void)scenario::run_scenario(world, options);
  return watch;
}

std::string described(const ClientWatch& watch) {
  std::string text;
  for (const Violation& v : watch.violations()) text += std::string(check_name(v.check)) + ": " + v.detail + "\n";
  return text;
}

TEST(ClientWatch, AWellBehavedClientPasses) {
  const ClientWatch watch = watched_run("", "timeline:\n  - {at: 1s, disconnect: {}}\n");
  EXPECT_EQ(watch.violation_count(), 0u) << described(watch);
  EXPECT_TRUE(watch.ever_connected("truck-1"));
}

TEST(ClientWatch, AnAlteredMacIsNotByteExact) {
  const ClientWatch watch = watched_run("      misbehave: {corrupt_mac: true}\n", "");
  ASSERT_FALSE(watch.violations().empty());
  EXPECT_EQ(watch.violations().front().check, Check::client_echo);
  EXPECT_NE(watch.violations().front().detail.find("ack_time_mac"), std::string::npos) << described(watch);
  EXPECT_EQ(watch.violations().size(), 1u) << "one report per connection, the rest counted";
  EXPECT_GT(watch.violation_count(), 100u);
}

TEST(ClientWatch, EchoingAnOldPairIsNotCurrent) {
  const ClientWatch watch = watched_run("      misbehave: {stop_echo: true}\n", "");
  ASSERT_FALSE(watch.violations().empty());
  EXPECT_EQ(watch.violations().front().check, Check::client_echo);
  EXPECT_NE(watch.violations().front().detail.find("superseded"), std::string::npos) << described(watch);
  // Not before the bound: the first pair is superseded 10 ms after it was sent.
  EXPECT_GE(watch.violations().front().at, Micros{500'000});
}

TEST(ClientWatch, ASlowReconnectFailsItsBound) {
  // The in-process client reconnects after its backoff; a bound below it must fail, with the time.
  const std::string timeline = "timeline:\n  - {at: 1s, disconnect: {}}\n";
  const ClientWatch strict = watched_run("", timeline, ClientBounds{Micros{500'000}, Micros{1}});
  ASSERT_EQ(strict.violations().size(), 1u) << described(strict);
  EXPECT_EQ(strict.violations().front().check, Check::client_reconnect);
  EXPECT_NE(strict.violations().front().detail.find("closed the connection at 1000 ms"), std::string::npos)
      << described(strict);
  EXPECT_EQ(watched_run("", timeline).violation_count(), 0u);
}

}  // namespace
}  // namespace ocp::campaign
