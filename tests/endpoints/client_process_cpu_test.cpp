// sim_app::ClientProcess::cpu_seconds: the CPU of a launched client's whole process group,
// including the real client behind a `/bin/sh -c` line, which the harness never reaps (it is
// killed with its group and reaped by init), so getrusage(RUSAGE_CHILDREN) cannot see it.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "sim_app/client_process.hpp"

namespace ocp::sim_app {
namespace {

using namespace std::chrono_literals;

TEST(ClientProcessCpu, AShellLinesRealClientIsCountedWhenItIsKilled) {
  // `; true` keeps the shell from exec'ing: the busy loop is the shell's child, in its group.
  auto launched = ClientProcess::launch({"/bin/sh", "-c", "sh -c 'while :; do :; done'; true"}, 0, "");
  ASSERT_TRUE(launched.ok()) << launched.error().message();
  ClientProcess& process = **launched;
  EXPECT_EQ(process.cpu_seconds(), 0.0);   // nothing read before it is stopped
  std::this_thread::sleep_for(2s);
  process.kill();
  EXPECT_FALSE(process.running());
  // ~2 s on an idle machine; ~0.2 s at a load of 17 on 2 cores. Counting only the shell (the
  // harness's RUSAGE_CHILDREN) reads about 0.
  EXPECT_GT(process.cpu_seconds(), 0.02);
  EXPECT_LT(process.cpu_seconds(), 60.0);
}

TEST(ClientProcessCpu, AClientThatEndsOnItsOwnIsCountedWhenItIsReaped) {
  auto launched = ClientProcess::launch(
      {"/bin/sh", "-c", "i=0; while [ $i -lt 300000 ]; do i=$((i+1)); done"}, 0, "");
  ASSERT_TRUE(launched.ok()) << launched.error().message();
  ClientProcess& process = **launched;
  const auto deadline = std::chrono::steady_clock::now() + 60s;
  while (process.running() && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(10ms);
  ASSERT_FALSE(process.running());
  EXPECT_EQ(process.exit_status(), 0);
  EXPECT_GT(process.cpu_seconds(), 0.01);
}

}  // namespace
}  // namespace ocp::sim_app
