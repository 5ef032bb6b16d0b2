// Ctrl-C in every tool (ocp/interrupt.hpp): the first signal asks the run to stop; the same
// signal delivered twice at once (timeout(1) signals its child and then its process group) is
// still one Ctrl-C; a second one a second later ends the process with 130.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <cstdlib>
#include <thread>

#include "ocp/interrupt.hpp"

namespace {

// Each case runs in a child process (a death test), so the handlers never reach this one.
TEST(Interrupt, OneSignalDeliveredTwiceAtOnceOnlyAsksTheRunToStop) {
  EXPECT_EXIT(
      {
        ocp::cli::install_interrupt_handlers();
        raise(SIGINT);
        raise(SIGINT);
        std::exit(ocp::cli::interrupt_requested() ? 7 : 8);
      },
      testing::ExitedWithCode(7), "");
}

TEST(Interrupt, ASecondSignalLaterEndsTheProcessWith130) {
  EXPECT_EXIT(
      {
        ocp::cli::install_interrupt_handlers();
        raise(SIGTERM);
        std::this_thread::sleep_for(std::chrono::milliseconds(1100));
        raise(SIGINT);
        std::exit(0);   // not reached
      },
      testing::ExitedWithCode(ocp::cli::exit_interrupted), "");
}

}  // namespace
