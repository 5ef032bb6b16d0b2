// OCP_INVARIANT stops the process with the condition and the reason in every build, release
// included; OCP_INVARIANT_DEEP only in the builds that check invariants (sanitizer, fuzz), and
// costs nothing in release builds.
#include "ocp/invariant.hpp"

#include <gtest/gtest.h>

#include "ocp/virtual_executor.hpp"

namespace ocp {
namespace {

TEST(Invariant, ABrokenInvariantStopsTheProcessAndSaysWhyInEveryBuild) {
  EXPECT_DEATH(OCP_INVARIANT(1 + 1 == 3, "arithmetic holds"), "invariant broken: 1 \\+ 1 == 3 \\(arithmetic holds\\)");
}

#if defined(OCP_INVARIANTS)
TEST(Invariant, ABrokenDeepInvariantStopsTheProcessAndSaysWhy) {
  EXPECT_DEATH(OCP_INVARIANT_DEEP(1 + 1 == 3, "arithmetic holds"), "invariant broken: 1 \\+ 1 == 3 \\(arithmetic holds\\)");
}
#else
TEST(Invariant, ReleaseBuildsDoNotEvaluateADeepCondition) {
  int evaluated = 0;
  OCP_INVARIANT_DEEP(++evaluated == 0, "never checked here");
  EXPECT_EQ(evaluated, 0);
}
#endif

TEST(Invariant, AHeldInvariantLetsTheRunGoOn) {
  VirtualExecutor executor;
  int ran = 0;
  (void)executor.call_at(SimTime{5}, [&] { ++ran; });
  (void)executor.call_at(SimTime{3}, [&] { ++ran; });
  while (executor.step()) {
  }
  EXPECT_EQ(ran, 2);
  EXPECT_EQ(executor.now(), SimTime{5});
}

}  // namespace
}  // namespace ocp
