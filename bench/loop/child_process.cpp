#include "child_process.hpp"

#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <thread>

namespace ocp::bench {

std::vector<std::string> substitute_port(std::vector<std::string> args, std::uint16_t port) {
  const std::string placeholder = "{port}";
  const std::string value = std::to_string(port);
  for (std::string& arg : args) {
    for (auto at = arg.find(placeholder); at != std::string::npos; at = arg.find(placeholder, at + value.size())) {
      arg.replace(at, placeholder.size(), value);
    }
  }
  return args;
}

namespace {
int decode_status(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}
}  // namespace

bool ChildProcess::start(const std::vector<std::string>& args, std::uint16_t port, std::string& error) {
  std::vector<std::string> substituted = substitute_port(args, port);
  std::vector<char*> argv;
  for (std::string& arg : substituted) argv.push_back(arg.data());
  argv.push_back(nullptr);
  const std::string port_text = std::to_string(port);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) {
    error = std::string("fork: ") + std::strerror(errno);
    return false;
  }
  if (pid == 0) {
    // Own process group, so stop() also reaches whatever the command starts (a shell's children).
    setpgid(0, 0);
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(127);   // the bench died between fork and prctl
    // The client's own output goes to our stderr: stdout is the report (pipe it to a file).
    dup2(STDERR_FILENO, STDOUT_FILENO);
    setenv("OCP_PORT", port_text.c_str(), 1);
    execvp(argv[0], argv.data());
    _exit(127);
  }
  setpgid(pid, pid);   // also from the parent: no race with an early stop()
  pid_ = pid;
  status_.reset();
  return true;
}

std::optional<int> ChildProcess::poll() {
  if (pid_ <= 0 || status_) return status_;
  int status = 0;
  if (waitpid(pid_, &status, WNOHANG) == pid_) status_ = decode_status(status);
  return status_;
}

void ChildProcess::stop() {
  if (pid_ <= 0) return;
  if (!poll()) {
    kill(-pid_, SIGTERM);
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(2);
    while (!poll() && std::chrono::steady_clock::now() < give_up) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (!poll()) {
      kill(-pid_, SIGKILL);
      int status = 0;
      if (waitpid(pid_, &status, 0) == pid_) status_ = decode_status(status);
    }
  }
  kill(-pid_, SIGKILL);   // anything the child left behind in its group
  pid_ = -1;
}

}  // namespace ocp::bench
