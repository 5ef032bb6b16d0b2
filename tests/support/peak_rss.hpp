// A program run to its end with its peak resident memory (wait4's ru_maxrss): for the tests
// that hold a long run's memory flat (issue #36). Output goes to /dev/null. Under
// AddressSanitizer the numbers mean nothing (its shadow and quarantine), so
// memory_is_measurable() says to skip.
#pragma once

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>
#include <vector>

namespace ocp::testing_support {

struct MeasuredRun {
  int exit_code = -1;
  long peak_rss_kib = 0;
};

inline MeasuredRun run_measuring_memory(const std::vector<std::string>& argv) {
  std::vector<char*> args;
  for (const std::string& arg : argv) args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);
  MeasuredRun run;
  const pid_t child = ::fork();
  if (child < 0) return run;
  if (child == 0) {
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, STDOUT_FILENO);
    ::dup2(null, STDERR_FILENO);
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  int status = 0;
  rusage usage{};
  if (::wait4(child, &status, 0, &usage) != child) return run;
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.peak_rss_kib = usage.ru_maxrss;
  return run;
}

constexpr bool memory_is_measurable() {
#if defined(__SANITIZE_ADDRESS__)
  return false;
#else
  return true;
#endif
}

}  // namespace ocp::testing_support
