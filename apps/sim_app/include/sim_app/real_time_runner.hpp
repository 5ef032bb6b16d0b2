#pragma once
// The real-time run loop of a simulator executable: one io_context on the calling thread,
// an AsioExecutor on it, SIGINT/SIGTERM/SIGHUP handling and an optional run duration.
//
//   sim_app::RealTimeRunner runner;                        // declare first: destroyed last
//   … build the world on runner.executor(), servers on runner.io() …
//   runner.set_on_shutdown([&](const std::string& why) { world.stop(); server.stop(); });
//   return runner.run(options.duration());
//
// Shutdown (a signal, the duration elapsing, or request_stop) calls on_shutdown once, on the
// io thread, then stops the io_context; run() returns the exit code (0 unless request_stop
// was given another one).
#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <functional>
#include <optional>
#include <string>

#include "ocp/asio/executor.hpp"
#include "ocp/log.hpp"

namespace ocp::sim_app {

// "SIGINT", "SIGTERM", "SIGHUP": the reason a run stopped, as the log says it.
const char* signal_name(int signal_number);

class RealTimeRunner {
 public:
  // leave_to_caller: the caller watches SIGINT/SIGTERM itself (a tool running several worlds
  // on threads, ocp/interrupt.hpp) and stops the run with request_stop.
  enum class Signals { handle, leave_to_caller };
  explicit RealTimeRunner(Signals signals = Signals::handle);
  ~RealTimeRunner();
  RealTimeRunner(const RealTimeRunner&) = delete;
  RealTimeRunner& operator=(const RealTimeRunner&) = delete;

  boost::asio::io_context& io() { return io_; }
  AsioExecutor& executor() { return executor_; }

  void set_on_shutdown(std::function<void(const std::string& reason)> on_shutdown);
  // Logs "shutting down: <reason>" through `logger` when set.
  void set_logger(const Logger* logger) { logger_ = logger; }
  // Begins shutdown (idempotent: the first call's reason and exit code win).
  void request_stop(const std::string& reason, int exit_code = 0);
  bool stopping() const { return stopping_; }

  // Blocks until shutdown; `duration` = nullopt runs until a signal arrives.
  [[nodiscard]] int run(std::optional<Micros> duration);

 private:
  boost::asio::io_context io_;
  AsioExecutor executor_;
  boost::asio::signal_set signals_;
  std::function<void(const std::string&)> on_shutdown_;
  const Logger* logger_ = nullptr;
  Executor::TimerId duration_timer_ = 0;
  bool stopping_ = false;
  int exit_code_ = 0;
};

}  // namespace ocp::sim_app
