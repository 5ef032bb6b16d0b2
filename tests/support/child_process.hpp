#pragma once
// The tests' one way to run another program: a child started with posix_spawn (no code runs
// between fork and exec, so nothing can hang there, as setenv could), its stdout and stderr on
// one pipe that no other child inherits (O_CLOEXEC: only the dup2'd copy crosses the exec).
//  * run_command(shell command): runs it through /bin/sh -c to the end, output and exit code;
//  * ChildProcess(argv): runs a program while the test talks to it: wait_for(text), signal(),
//    wait_exit(); killed (SIGKILL) and reaped if still running when it goes out of scope.
// Real time, so each wait has a limit; the suites that use it are labelled realtime.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <vector>

extern char** environ;

namespace ocp::test {

class ChildProcess {
 public:
  explicit ChildProcess(const std::vector<std::string>& arguments) {
    int fds[2];
    if (arguments.empty() || pipe2(fds, O_CLOEXEC) != 0) return;
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
    posix_spawn_file_actions_adddup2(&actions, fds[1], STDERR_FILENO);
    std::vector<char*> argv;
    for (const std::string& argument : arguments) argv.push_back(const_cast<char*>(argument.c_str()));
    argv.push_back(nullptr);
    if (posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&actions);
    close(fds[1]);
    out_ = fds[0];
  }
  ~ChildProcess() {
    if (pid_ > 0 && exit_code_ == still_running) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
    if (out_ >= 0) close(out_);
  }
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  bool started() const { return pid_ > 0; }
  // Reads until `text` has appeared (true) or `limit` passed or the output ended (false).
  bool wait_for(const std::string& text, std::chrono::milliseconds limit) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (output_.find(text) == std::string::npos) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0 || !read_some(static_cast<int>(left.count()))) return false;
    }
    return true;
  }
  // The exit code once it exited within `limit`; 1000 + signal when a signal ended it; -1 when
  // it had not exited by then (it is killed when the object goes out of scope).
  int wait_exit(std::chrono::milliseconds limit) {
    if (pid_ <= 0) return -1;
    if (exit_code_ != still_running) return exit_code_;
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (true) {
      while (read_some(10)) {}
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        while (read_some(0)) {}
        exit_code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 1000 + WTERMSIG(status);
        return exit_code_;
      }
      if (std::chrono::steady_clock::now() >= deadline) return -1;
    }
  }
  void signal(int number) {
    if (pid_ > 0 && exit_code_ == still_running) kill(pid_, number);
  }
  const std::string& output() const { return output_; }

 private:
  static constexpr int still_running = -2;
  bool read_some(int timeout_ms) {
    if (out_ < 0) return false;
    pollfd fd{out_, POLLIN, 0};
    if (poll(&fd, 1, timeout_ms) <= 0) return false;
    char buffer[4096];
    const ssize_t n = read(out_, buffer, sizeof buffer);
    if (n <= 0) return false;
    output_.append(buffer, static_cast<std::size_t>(n));
    return true;
  }
  pid_t pid_ = -1;
  int out_ = -1;
  int exit_code_ = still_running;
  std::string output_;
};

struct CommandRun {
  int exit_code = -1;   // 1000 + signal when a signal ended it; -1 when it did not end in time
  std::string output;   // stdout and stderr, interleaved as written
};

// `command` through /bin/sh -c (so it may hold redirections and quoting), to the end.
inline CommandRun run_command(const std::string& command,
                              std::chrono::milliseconds limit = std::chrono::minutes(5)) {
  ChildProcess child({"/bin/sh", "-c", command});
  CommandRun run;
  run.exit_code = child.wait_exit(limit);
  run.output = child.output();
  return run;
}

}  // namespace ocp::test
