// SIGINT / SIGTERM → a flag (interrupt.hpp).
#include "scenario/interrupt.hpp"

#include <csignal>

namespace ocp::scenario {
namespace {

volatile std::sig_atomic_t interrupt_flag = 0;

void on_interrupt_signal(int) { interrupt_flag = 1; }

}  // namespace

void catch_interrupts() {
  struct sigaction action {};
  action.sa_handler = on_interrupt_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;   // a write of the reports is not cut short by a second Ctrl-C
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

bool interrupt_requested() { return interrupt_flag != 0; }
void request_interrupt() { interrupt_flag = 1; }
void clear_interrupt() { interrupt_flag = 0; }

}  // namespace ocp::scenario
