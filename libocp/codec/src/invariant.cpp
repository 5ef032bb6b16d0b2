#include "ocp/invariant.hpp"

#include <cstdio>
#include <cstdlib>

namespace ocp {

void invariant_failed(const char* condition, const char* why, const char* file, int line) {
  // No logger: the process is in a state we promised never to reach, so write plainly and stop.
  std::fprintf(stderr, "%s:%d: invariant broken: %s (%s)\n", file, line, condition, why);
  std::fflush(stderr);
  std::abort();
}

}  // namespace ocp
