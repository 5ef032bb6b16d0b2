#pragma once
// ChildProcess: the user's client launched by `ocp_bench loop -- command args…`. `{port}` in
// any argument is replaced by the Streamer's port, which is also in the environment as
// OCP_PORT. The child runs in its own process group and is killed (SIGTERM, then SIGKILL after
// a grace period) by stop() and the destructor, so every exit path of the bench ends it; it
// also gets SIGKILL from the kernel if the bench itself dies (PR_SET_PDEATHSIG). Its stdout is
// redirected to the bench's stderr, so the bench's stdout carries only the report.
#include <sys/types.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace ocp::bench {

std::vector<std::string> substitute_port(std::vector<std::string> args, std::uint16_t port);

class ChildProcess {
 public:
  ChildProcess() = default;
  ~ChildProcess() { stop(); }
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  // False (with `error` set) when fork fails; an exec failure shows as exit code 127.
  bool start(const std::vector<std::string>& args, std::uint16_t port, std::string& error);
  // Exit status once the child has ended (non-blocking check): the exit code, or 128 + signal.
  std::optional<int> poll();
  void stop();
  bool running() const { return pid_ > 0 && !status_; }

 private:
  pid_t pid_ = -1;
  std::optional<int> status_;
};

}  // namespace ocp::bench
