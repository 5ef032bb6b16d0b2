// Ctrl-C in every tool (ocp/interrupt.hpp): the first signal asks the run to stop; the same
// signal delivered twice at once (timeout(1) signals its child and then its process group) is
// still one Ctrl-C; a second one a second later ends the process with 130.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
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

TEST(Interrupt, SighupAsksTheRunToStopLikeSigterm) {
  EXPECT_EXIT(
      {
        ocp::cli::install_interrupt_handlers();
        raise(SIGHUP);
        std::exit(ocp::cli::interrupt_requested() ? 7 : 8);
      },
      testing::ExitedWithCode(7), "");
}

// A closed stdout (`| head -c1`) makes a write fail with EPIPE instead of killing the tool.
TEST(Interrupt, AClosedPipeIsAFailedWriteNotTheEnd) {
  EXPECT_EXIT(
      {
        ocp::cli::install_interrupt_handlers();
        int fds[2];
        if (pipe(fds) != 0) std::exit(9);
        close(fds[0]);
        const bool failed = write(fds[1], "x", 1) < 0 && errno == EPIPE;
        std::exit(failed ? 7 : 8);
      },
      testing::ExitedWithCode(7), "");
}

}  // namespace
