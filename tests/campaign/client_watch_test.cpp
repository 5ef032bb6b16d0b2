// ClientWatch (campaign/client_watch.hpp), the client-facing checks of `ocp_campaign run
// --client`, in virtual time on the in-process reference client: a well-behaved client passes,
// and each check comes out failed for the client that breaks it.
#include <gtest/gtest.h>

#include <deque>
#include <string>

#include "campaign/client_watch.hpp"
#include "scenario/parse.hpp"
#include "ocp/virtual_executor.hpp"
#include "scenario/runner.hpp"
#include "world/world.hpp"

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

// Hand-made Streamer frames for a watch attached to a world that never starts: pairs sent every
// 10 ms, echoes at chosen times.
class EchoFeed {
 public:
  EchoFeed() : world_(executor_, WorldConfig{}, [](const LogRecord&) {}) {
    watch_.attach(world_);
    publish(0, ConnectionEvent{Wire::vehicle, ConnectionChange::opened, "127.0.0.1:1", nullptr});
  }
  void send_pairs(std::int64_t from_ms, std::int64_t to_ms) {
    for (std::int64_t ms = from_ms; ms <= to_ms; ms += 10) {
      WireFrame frame;
      frame.kind = WireMessageKind::control;
      frame.ack = AckPair{static_cast<std::uint64_t>(ms) * 1000, 7};
      publish(ms * 1000, frame);
    }
  }
  void echo(std::int64_t at_us, std::uint64_t ack_time) {
    payloads_.push_back("{\"ack_time\":" + std::to_string(ack_time) + ",\"ack_time_mac\":7}");
    WireFrame frame;
    frame.direction = FrameDirection::in;
    frame.kind = WireMessageKind::vehicle_response;
    frame.payload = payloads_.back();
    frame.ack = AckPair{ack_time, 7};
    publish(at_us, frame);
  }
  const ClientWatch& watch() const { return watch_; }

 private:
  void publish(std::int64_t at_us, EventBody body) {
    world_.events().publish(Event{SimTime{at_us}, Component{ComponentKind::streamer, "truck-1"}, std::move(body)});
  }
  VirtualExecutor executor_;
  World world_;
  ClientWatch watch_{ClientBounds{}};
  std::deque<std::string> payloads_;
};

TEST(ClientWatch, OneStaleEchoAfterAStallIsAClientThatWasNotScheduled) {
  EchoFeed feed;
  feed.send_pairs(0, 700);
  feed.echo(700'000, 0);         // its keep-alive fired first on waking: the pair of 0 ms, 690 ms stale
  feed.echo(700'050, 700'000);   // then it read what came meanwhile
  feed.send_pairs(710, 1500);
  feed.echo(1'500'000, 20'000);  // stale again, but the run of stale echoes starts here
  feed.echo(1'500'100, 1'500'000);
  EXPECT_EQ(feed.watch().violation_count(), 0u) << described(feed.watch());
}

TEST(ClientWatch, StaleEchoesInARowAreAClientThatDoesNotTakeTheNewestPair) {
  EchoFeed feed;
  feed.send_pairs(0, 1500);
  for (std::int64_t at = 600'000; at <= 900'000; at += 10'000) feed.echo(at, 0);
  ASSERT_EQ(feed.watch().violations().size(), 1u) << described(feed.watch());
  EXPECT_EQ(feed.watch().violations().front().at, SimTime{850'000}) << "stale from 600 ms, 250 ms in a row";
  EXPECT_NE(feed.watch().violations().front().detail.find("only stale pairs for 250 ms"), std::string::npos)
      << described(feed.watch());
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
