// Where the shim library is (controller.hpp, find_shim): $OCP_VTIME_SHIM, else beside the
// running program, as built (build/bin and build/lib) and as installed (lib/ocp-sim).
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <string>

#include "vtime/controller.hpp"

namespace ocp::vtime {

namespace {

std::string exe_dir() {
  char buffer[4096];
  const ssize_t size = readlink("/proc/self/exe", buffer, sizeof buffer - 1);
  if (size <= 0) return {};
  std::string path(buffer, static_cast<std::size_t>(size));
  return path.substr(0, path.rfind('/'));
}

bool is_file(const std::string& path) {
  struct stat info{};
  return ::stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode);
}

}  // namespace

std::string find_shim() {
  if (const char* set = std::getenv("OCP_VTIME_SHIM"); set != nullptr && *set != '\0') return is_file(set) ? set : "";
  const std::string dir = exe_dir();
  for (const char* relative : {"/../lib/ocp-sim/libocp_vtime_shim.so", "/../lib/libocp_vtime_shim.so", "/libocp_vtime_shim.so"}) {
    if (is_file(dir + relative)) return dir + relative;
  }
  return "";
}

}  // namespace ocp::vtime
