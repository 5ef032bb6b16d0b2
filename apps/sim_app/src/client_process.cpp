#include "sim_app/client_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;  // POSIX: the process environment (unistd.h declares it only with _GNU_SOURCE)

#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <deque>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "process_group_cpu.hpp"
#include "sim_app/proc_stat.hpp"

namespace ocp::sim_app {
namespace {

// Live children, for kill_all_clients() from a signal handler: a fixed array of atomics.
constexpr std::size_t max_children = 64;
std::array<std::atomic<pid_t>, max_children> live_children{};

void remember(pid_t pid) {
  for (auto& slot : live_children) {
    pid_t empty = 0;
    if (slot.compare_exchange_strong(empty, pid)) return;
  }
}

void forget(pid_t pid) {
  for (auto& slot : live_children) {
    pid_t expected = pid;
    if (slot.compare_exchange_strong(expected, 0)) return;
  }
}

}  // namespace

std::string describe_exit_status(int status) {
  if (status <= 128) return "exited with code " + std::to_string(status);
  const int signal_number = status - 128;
  const char* name = sigabbrev_np(signal_number);
  return "was killed by signal " + std::to_string(signal_number) +
         (name ? std::string(" (SIG") + name + ")" : std::string());
}

std::string last_lines_of(const std::string& path, std::size_t count) {
  std::ifstream in(path, std::ios::binary);
  if (path.empty() || !in) return "";
  std::deque<std::string> lines;
  std::string line;
  while (std::getline(in, line)) {
    if (line.size() > 300) line = line.substr(0, 300) + " …";  // a client may write anything
    lines.push_back(std::move(line));
    if (lines.size() > count) lines.pop_front();
  }
  std::string out;
  for (const std::string& kept : lines) out += "\n    " + kept;
  return out;
}

std::vector<std::string> substitute_port(const std::vector<std::string>& command, std::uint16_t port) {
  std::vector<std::string> out;
  const std::string value = std::to_string(port);
  for (std::string arg : command) {
    for (std::size_t at = arg.find("{port}"); at != std::string::npos; at = arg.find("{port}", at + value.size())) {
      arg.replace(at, 6, value);
    }
    out.push_back(std::move(arg));
  }
  return out;
}

namespace {

// The child's environment, built before fork: between fork and exec the child may only make
// async-signal-safe calls. setenv allocates, and in a multi-threaded harness (-j N) another
// thread may hold the allocator's lock at the fork, so a child that called it could hang
// before exec, and the parent with it, waiting for the status pipe.
std::vector<std::string> child_environment(std::uint16_t port, const std::vector<std::string>& extra_environment) {
  std::vector<std::string> environment;
  const auto replaced = [&](const char* entry) {
    if (std::strncmp(entry, "OCP_PORT=", 9) == 0) return true;
    for (const std::string& extra : extra_environment) {
      const auto name = extra.substr(0, extra.find('=') + 1);
      if (std::strncmp(entry, name.c_str(), name.size()) == 0) return true;
    }
    return false;
  };
  for (char** entry = environ; *entry != nullptr; ++entry) {
    if (!replaced(*entry)) environment.emplace_back(*entry);
  }
  environment.push_back("OCP_PORT=" + std::to_string(port));
  environment.insert(environment.end(), extra_environment.begin(), extra_environment.end());
  return environment;
}

// The child, between fork and exec (async-signal-safe calls only): its own process group, gone
// with the harness, no inherited descriptors, output to the log; an exec failure is written to
// the status pipe.
[[noreturn]] void exec_child(char* const* argv, char* const* envp, const std::string& log_path, int status_write_end) {
  setpgid(0, 0);
  // Even if the harness dies without cleaning up (a crash, SIGKILL), the client goes too.
  // (The launching worker thread outlives its clients: it kills them before it returns.)
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (getppid() == 1) _exit(127);
  // The harness's sockets (listening socket, connections) must not live on in the client:
  // an inherited listener would keep the port busy across a Streamer restart.
  const long max_fd = sysconf(_SC_OPEN_MAX);
  for (int fd = 3; fd < (max_fd > 0 ? max_fd : 1024); ++fd) {
    if (fd != status_write_end) close(fd);
  }
  const bool to_own_stderr = log_path == ClientProcess::to_stderr;
  const int fd =
      to_own_stderr ? -1 : open(log_path.empty() ? "/dev/null" : log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (to_own_stderr) {
    dup2(STDERR_FILENO, STDOUT_FILENO);
  } else if (fd >= 0) {
    dup2(fd, STDOUT_FILENO);
    dup2(fd, STDERR_FILENO);
    close(fd);
  }
  const int null_in = open("/dev/null", O_RDONLY);
  if (null_in >= 0) dup2(null_in, STDIN_FILENO);
  execvpe(argv[0], argv, envp);
  const int error = errno;
  (void)!write(status_write_end, &error, sizeof error);
  _exit(127);
}

}  // namespace

Result<std::unique_ptr<ClientProcess>> ClientProcess::launch(const std::vector<std::string>& command,
                                                             std::uint16_t port, const std::string& log_path,
                                                             const std::vector<std::string>& extra_environment) {
  if (command.empty()) return Error{std::make_error_code(std::errc::invalid_argument), "no client command"};
  const std::vector<std::string> args = substitute_port(command, port);
  std::vector<char*> argv;
  for (const std::string& arg : args) argv.push_back(const_cast<char*>(arg.c_str()));
  argv.push_back(nullptr);
  std::vector<std::string> environment = child_environment(port, extra_environment);
  std::vector<char*> envp;
  for (std::string& entry : environment) envp.push_back(entry.data());
  envp.push_back(nullptr);

  // An exec failure is reported through a close-on-exec pipe: EOF means exec succeeded.
  int status_pipe[2];
  if (pipe2(status_pipe, O_CLOEXEC) != 0) {
    return Error{std::error_code(errno, std::generic_category()), "pipe2 failed"};
  }
  const pid_t pid = fork();
  if (pid < 0) {
    close(status_pipe[0]);
    close(status_pipe[1]);
    return Error{std::error_code(errno, std::generic_category()), "fork failed"};
  }
  if (pid == 0) {
    close(status_pipe[0]);
    exec_child(argv.data(), envp.data(), log_path, status_pipe[1]);
  }
  setpgid(pid, pid);  // also from the parent: no race with kill before the child ran
  remember(pid);
  close(status_pipe[1]);
  int exec_error = 0;
  ssize_t got;
  do {
    got = read(status_pipe[0], &exec_error, sizeof exec_error);
  } while (got < 0 && errno == EINTR);
  close(status_pipe[0]);
  std::unique_ptr<ClientProcess> process(new ClientProcess(pid));
  if (got == static_cast<ssize_t>(sizeof exec_error)) {
    process->kill();
    return Error{std::error_code(exec_error, std::generic_category()),
                 "cannot run client '" + args[0] + "': " + std::strerror(exec_error)};
  }
  return process;
}

ClientProcess::~ClientProcess() { kill(); }

bool ClientProcess::running() {
  if (exit_status_) return false;
  int status = 0;
  rusage usage{};
  const pid_t done = wait4(pid_, &status, WNOHANG, &usage);
  if (done == pid_) {
    exit_status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    forget(pid_);
    // It ended on its own: its own CPU (with what it reaped), and what it left in its group.
    if (!cpu_seconds_) cpu_seconds_ = sim_app::cpu_seconds(usage) + process_group_cpu_seconds(pid_);
    ::kill(-pid_, SIGKILL);  // anything it left behind in its group
    return false;
  }
  return true;
}

void ClientProcess::kill() {
  if (!running()) return;
  cpu_seconds_ = process_group_cpu_seconds(pid_);
  ::kill(-pid_, SIGTERM);
  // Grace period for a clean exit, bounded; then SIGKILL the whole group.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(1000);
  while (running() && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  if (running()) {
    ::kill(-pid_, SIGKILL);
    int status = 0;
    waitpid(pid_, &status, 0);
    exit_status_ = 128 + SIGKILL;
    forget(pid_);
  }
}

void kill_all_clients() noexcept {
  for (auto& slot : live_children) {
    const pid_t pid = slot.load();
    if (pid > 0) ::kill(-pid, SIGKILL);
  }
}

}  // namespace ocp::sim_app
