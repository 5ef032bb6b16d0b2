#include "sim_app/real_time_runner.hpp"

#include <fmt/format.h>

#include <sys/prctl.h>

#include <csignal>
#include <utility>

namespace ocp::sim_app {

const char* signal_name(int signal_number) {
  switch (signal_number) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    default: return "a signal";
  }
}

RealTimeRunner::RealTimeRunner(Signals signals) : executor_(io_), signals_(io_) {
  // Linux lets timers of this thread fire up to 50 µs late by default (timer slack) to batch
  // wake-ups; that would show up directly as lateness of the 10 ms control tick.
  prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
  // A closed stdout (the console log piped into `head`) must not end the simulation.
  std::signal(SIGPIPE, SIG_IGN);
  // Catch SIGINT/SIGTERM/SIGHUP from construction on: a signal that arrives while the program is
  // still starting (its port may already accept connections) is queued, not fatal. SIGHUP (a
  // closed SSH session, a CI runner's cancel) ends a run as SIGTERM does.
  if (signals == Signals::leave_to_caller) return;
  boost::system::error_code ignored;
  for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) signals_.add(signal_number, ignored);
}

RealTimeRunner::~RealTimeRunner() {
  boost::system::error_code ignored;
  signals_.cancel(ignored);
}

void RealTimeRunner::set_on_shutdown(std::function<void(const std::string&)> on_shutdown) {
  on_shutdown_ = std::move(on_shutdown);
}

void RealTimeRunner::request_stop(const std::string& reason, int exit_code) {
  if (stopping_) return;
  stopping_ = true;
  exit_code_ = exit_code;
  if (logger_) logger_->info("shutting down: {}", reason);
  executor_.cancel(duration_timer_);
  boost::system::error_code ignored;
  signals_.cancel(ignored);
  if (on_shutdown_) on_shutdown_(reason);
  // Whatever is still pending (reads on closed sockets, timers) is dropped with the
  // io_context; the cores have stopped, so nothing is left to say.
  io_.stop();
}

int RealTimeRunner::run(std::optional<Micros> duration) {
  signals_.async_wait([this](const boost::system::error_code& wait_error, int signal_number) {
    if (wait_error) return;
    request_stop(fmt::format("{} received", signal_name(signal_number)));
  });
  if (duration) {
    duration_timer_ = executor_.call_after(*duration, [this, duration] {
      request_stop(fmt::format("--duration-s {:g} elapsed", static_cast<double>(duration->count()) / 1e6));
    });
  }
  if (!stopping_) io_.run();
  return exit_code_;
}

}  // namespace ocp::sim_app
