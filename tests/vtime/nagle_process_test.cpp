// Nagle's algorithm in virtual time, with a real client process (docs/virtual-time.md,
// "Nagle's algorithm"): a client that writes a 4-byte prefix and its payload in two writes
// without TCP_NODELAY has the payload held exactly until we next write to it, or 40 ms of
// virtual time when we write nothing; with TCP_NODELAY, or in one write, nothing is held.
#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "ocp/virtual_executor.hpp"
#include "sim_app/client_process.hpp"
#include "vtime/controller.hpp"

namespace ocp::vtime {
namespace {

constexpr SimTime at_ms(std::int64_t ms) { return SimTime{ms * 1000}; }

// What reached us, by the virtual millisecond it was handed over at.
using Arrivals = std::map<std::int64_t, std::string>;

// Our writes: "g" (write AAAA and BBBBBB) at 10 ms, an unrelated byte at 17 ms (its ACK rides
// on it), "g" again at 100 ms with nothing after it until "q" at 300 ms.
Arrivals run_split_writer(const std::string& mode) {
  VirtualExecutor executor;
  ControllerOptions options;
  options.shim_path = OCP_VTIME_SHIM_PATH;
  options.watchdog = std::chrono::milliseconds(60'000);
  Controller controller(executor, options);
  Arrivals arrivals;
  std::shared_ptr<ByteStream> connection;
  const int listener = controller.listen(0, [&](std::shared_ptr<ByteStream> stream) {
    connection = stream;
    ByteStreamHandlers handlers;
    handlers.on_bytes = [&](std::string_view bytes) { arrivals[executor.now().count() / 1000] += std::string(bytes); };
    stream->set_handlers(std::move(handlers));
  });
  const std::string script = std::string(OCP_VTIME_TEST_CLIENTS) + "/split_writer.py";
  auto launched = sim_app::ClientProcess::launch({OCP_PYTHON3_PATH, script, "{port}", mode}, controller.port(listener), "",
                                                 controller.environment());
  EXPECT_TRUE(launched.ok());
  if (!launched.ok()) return arrivals;
  std::shared_ptr<sim_app::ClientProcess> process = std::move(*launched);
  controller.expect_process(process->pid(), "split_writer.py", [process] { return process->running(); });
  // Connected at virtual time 0 (a connect waits in the shim for the handshake).
  controller.run_until(at_ms(5), {});
  EXPECT_TRUE(connection != nullptr) << "the client did not connect";
  if (connection == nullptr) return arrivals;
  for (const auto& [ms, byte] : std::vector<std::pair<int, const char*>>{{10, "g"}, {17, "n"}, {100, "g"}, {300, "q"}}) {
    executor.call_at(at_ms(ms), [&, byte = byte] { connection->write(byte); });
  }
  controller.run_until(at_ms(400), {});
  return arrivals;
}

TEST(VirtualTimeNagle, ASplitWriteIsHeldUntilOurNextWriteOrTheDelayedAck) {
  const Arrivals arrivals = run_split_writer("split");
  // 17 ms: the ACK rides on our byte. 140 ms: we wrote nothing after 100 ms, so the payload
  // waits for the 40 ms delayed ACK of the prefix.
  EXPECT_EQ(arrivals, (Arrivals{{10, "AAAA"}, {17, "BBBBBB"}, {100, "AAAA"}, {140, "BBBBBB"}}));
}

TEST(VirtualTimeNagle, WithTcpNoDelayNothingIsHeld) {
  EXPECT_EQ(run_split_writer("split-nodelay"), (Arrivals{{10, "AAAABBBBBB"}, {100, "AAAABBBBBB"}}));
}

TEST(VirtualTimeNagle, OneWritePerFrameIsNeverHeld) {
  EXPECT_EQ(run_split_writer("whole"), (Arrivals{{10, "AAAABBBBBB"}, {100, "AAAABBBBBB"}}));
}

}  // namespace
}  // namespace ocp::vtime
