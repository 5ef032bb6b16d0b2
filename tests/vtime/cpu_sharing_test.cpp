// A world's controller and its client processes share one CPU, under SCHED_BATCH
// (vtime/src/cpu_pin.hpp): the client sees one CPU and the batch policy, the controller's
// thread gets its CPUs and policy back after the world, one /proc look is enough while pinned,
// and pin_cpu = false leaves everything as it was.
#include <gtest/gtest.h>
#include <sched.h>

#include <fstream>
#include <sstream>
#include <string>

#include "scratch_dir.hpp"
#include "virtual_run.hpp"

namespace ocp::vtime {
namespace {

struct Seen {
  std::string client;   // "CPUS POLICY" as the client saw them
  Ran ran;
};

// The Python example, after it wrote what it runs on to `path`.
Seen run_and_see(bool pin) {
  const testing_support::ScratchDir dir("ocp_cpu_sharing");
  const std::string path = (dir / "seen").string();
  const std::string program = "import os, runpy, sys\n"
                              "open(sys.argv[1], 'w').write('%d %d' % (len(os.sched_getaffinity(0)), os.sched_getscheduler(0)))\n"
                              "sys.argv = sys.argv[2:]\n"
                              "runpy.run_path(sys.argv[0], run_name='__main__')\n";
  ControllerOptions controller;
  controller.pin_cpu = pin;
  Seen seen;
  seen.ran = run_client(world_yaml("2s", "  faults:\n    - {fault: InvalidMac, never: true, from: 1s}\n"),
                        {OCP_PYTHON3_PATH, "-c", program, path, std::string(OCP_EXAMPLES_DIR) + "/vehicle_client.py", "127.0.0.1:{port}"},
                        controller);
  std::ifstream file(path);
  std::getline(file, seen.client);
  return seen;
}

int allowed_cpus() {
  cpu_set_t mask;
  return sched_getaffinity(0, sizeof mask, &mask) == 0 ? CPU_COUNT(&mask) : 0;
}

TEST(VirtualTimeCpuSharing, TheClientRunsOnTheControllersOneCpuUnderBatchScheduling) {
  const int before = allowed_cpus();
  const Seen pinned = run_and_see(true);
  expect_all_pass(pinned.ran);
  EXPECT_EQ(pinned.client, "1 " + std::to_string(SCHED_BATCH)) << "the client's CPU count and policy";
  EXPECT_GT(pinned.ran.run.stats.single_looks, 0U) << "pinned, one /proc look is enough";
  EXPECT_EQ(allowed_cpus(), before) << "the controller's thread gets its CPUs back";
  EXPECT_EQ(sched_getscheduler(0), SCHED_OTHER) << "and its policy";
}

TEST(VirtualTimeCpuSharing, WithoutThePinNothingChanges) {
  const int before = allowed_cpus();
  const Seen free = run_and_see(false);
  expect_all_pass(free.ran);
  EXPECT_EQ(free.client, std::to_string(before) + " " + std::to_string(SCHED_OTHER));
  EXPECT_EQ(free.ran.run.stats.single_looks, 0U) << "unpinned, every look is a double look";
}

}  // namespace
}  // namespace ocp::vtime
