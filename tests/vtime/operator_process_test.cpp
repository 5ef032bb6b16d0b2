// The :4001 operator client as a process in virtual time (vtime/client_world.hpp): beside one
// vehicle client process per external vehicle, examples/operator_client.py runs against the
// Player's operator API on the World's clock. It connects once, reads VehicleOcpShared and
// answers with ClientOcpShared the whole world long (its 0.5 s keep-alive, virtual), and a run
// is a pure function of its seed. The Controller's wall-clock watchdog bounds every run
// (std::chrono::steady_clock), so a hang fails the test instead of hanging it.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <vector>

#include "scenario/parse.hpp"
#include "vtime/client_world.hpp"
#include "world/world.hpp"

namespace ocp::vtime {
namespace {

const std::string operator_world =
    "seed: 11\nduration: 5s\nworld:\n  gamepad: drive\n  vehicles:\n    - name: truck-1\n      in_process_client: false\n"
    "      link: {delay: 10ms}\nexpect:\n  faults:\n    - {fault: InvalidMac, never: true, from: 1s}\n";

struct OperatorRun {
  VirtualClientRun run;
  PlayerStats player;
};

OperatorRun run_with_operator(bool trace) {
  const scenario::Scenario world = scenario::parse_scenario(operator_world, "operator.yaml");
  OperatorRun ran;
  scenario::RunOptions options;
  options.trace = trace;
  options.on_finished = [&ran](World& built) { ran.player = built.player().stats(); };
  VirtualClientOptions clients;
  clients.argv = {OCP_VEHICLE_CLIENT_PATH, "--no-status", "127.0.0.1:{port}"};
  clients.operator_argv = {OCP_PYTHON3_PATH, std::string(OCP_EXAMPLES_DIR) + "/operator_client.py", "127.0.0.1:{port}"};
  clients.controller.shim_path = OCP_VTIME_SHIM_PATH;
  clients.controller.watchdog = std::chrono::milliseconds(90'000);
  ran.run = run_with_virtual_clients(world, options, clients);
  return ran;
}

TEST(VirtualTimeOperatorProcess, ExampleOperatorClientStaysConnectedAndAnswersTheWholeWorld) {
  const auto start = std::chrono::steady_clock::now();
  const OperatorRun ran = run_with_operator(false);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(ran.run.result.ran, Micros{5'000'000});
  ASSERT_TRUE(ran.run.operator_client.has_value());
  EXPECT_EQ(ran.run.operator_client->vehicle, operator_name);
  EXPECT_TRUE(ran.run.operator_client->process->running()) << "the operator client must live through the world";
  EXPECT_EQ(ran.player.client_connections_accepted, 1u);
  EXPECT_EQ(ran.player.client_connections_closed, 0u) << "no read timeout, no bad frame: the connection lasted";
  // The Player publishes at 100 Hz and the client answers what it reads: hundreds of messages
  // in 5 s (at least its keep-alives, every 0.5 s, whatever it reads).
  EXPECT_GT(ran.player.client_frames_sent, 300u);
  EXPECT_GT(ran.player.client_messages_received, 10u);
  std::printf("vehicle client + operator client: 5 s simulated in %.2f s wall, %llu messages from the Player's client\n", wall,
              static_cast<unsigned long long>(ran.player.client_messages_received));
}

TEST(VirtualTimeOperatorProcess, SameSeedSameTraceWithTheOperatorClient) {
  const std::string first = run_with_operator(true).run.result.trace_jsonl;
  ASSERT_FALSE(first.empty());
  for (int again = 0; again < 2; ++again) {
    const std::string next = run_with_operator(true).run.result.trace_jsonl;
    EXPECT_EQ(next.size(), first.size()) << "run " << again + 2;
    EXPECT_TRUE(next == first) << "run " << again + 2 << ": the trace differs";
  }
}

}  // namespace
}  // namespace ocp::vtime
