#pragma once
// Where the programs find their data (issue 39): the web view's files, the campaign profiles and
// the rest of share/ocp-sim, without a path compiled in, so an installed or copied tree works
// wherever it lands. In this order:
//   1. $OCP_SIM_DATA, when set (then only there: an override that silently fell back would hide
//      a typo);
//   2. <the executable's folder>/../share/ocp-sim (an install: `cmake --install`, the .deb);
//   3. the build tree, for development: <the nearest folder above the executable holding a
//      CMakeCache.txt>/share/ocp-sim, which the build fills with links into the source tree.
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace ocp::sim_app {

inline constexpr const char* data_override_variable = "OCP_SIM_DATA";

// The data is not where any rule looked; what() names every place tried and the variable.
class DataNotFound : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct DataSearch {
  std::optional<std::string> override_dir;   // $OCP_SIM_DATA
  std::filesystem::path executable;          // /proc/self/exe
};

// The search of this process: $OCP_SIM_DATA and /proc/self/exe.
DataSearch this_process_data_search();

// The data folder's `relative` entry (a file or folder, e.g. "web", "campaign/profiles"):
// the first rule's folder that holds it. Throws DataNotFound otherwise.
std::filesystem::path find_data(const std::string& relative, const DataSearch& search);
std::filesystem::path find_data(const std::string& relative);

}  // namespace ocp::sim_app
