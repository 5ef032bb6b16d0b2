#pragma once
// Launches the client under test: `-- CMD ARGS…` with the port in env OCP_PORT and every
// "{port}" in the arguments replaced. The child gets its own process group, and is killed
// (SIGTERM, then SIGKILL after a grace period) on every path: destructor, kill(), and the
// harness's own SIGINT/SIGTERM (kill_all_clients, async-signal-safe).
#include <sys/types.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ocp/error.hpp"

namespace ocp::sim_app {

class ClientProcess {
 public:
  static constexpr const char* to_stderr = "-";
  // Output (stdout + stderr) goes to `log_path` ("" → /dev/null; to_stderr → the harness's own
  // stderr, so that the harness's stdout carries only its report). `environment` entries
  // ("NAME=value") are added to the child's, replacing its own of that name (virtual time's
  // LD_PRELOAD and control socket, vtime/).
  static Result<std::unique_ptr<ClientProcess>> launch(const std::vector<std::string>& command,
                                                       std::uint16_t port, const std::string& log_path,
                                                       const std::vector<std::string>& environment = {});
  ~ClientProcess();
  ClientProcess(const ClientProcess&) = delete;
  ClientProcess& operator=(const ClientProcess&) = delete;

  void kill();                       // idempotent; waits for the child
  bool running();                    // reaps it when it exited
  std::optional<int> exit_status() const { return exit_status_; }
  pid_t pid() const { return pid_; }
  // User + system seconds the client used: its whole process group (a `/bin/sh -c` line's
  // real client too, which the harness never reaps), read when it was killed or found ended;
  // 0 until then.
  double cpu_seconds() const { return cpu_seconds_.value_or(0); }

 private:
  explicit ClientProcess(pid_t child) : pid_(child) {}
  pid_t pid_;
  std::optional<int> exit_status_;
  std::optional<double> cpu_seconds_;   // read once, before the group is signalled
};

// "exited with code 3", "was killed by signal 11 (SIGSEGV)": an exit_status() in words.
std::string describe_exit_status(int status);
// The last `count` lines of a client's log, each indented, for a harness error; "" when the
// file is missing or empty.
std::string last_lines_of(const std::string& path, std::size_t count);

// Replaces "{port}" in every argument.
std::vector<std::string> substitute_port(const std::vector<std::string>& command, std::uint16_t port);
// Kills every client still running (from a signal handler: only async-signal-safe calls).
void kill_all_clients() noexcept;

}  // namespace ocp::sim_app
