// data_dir.hpp: the three rules, in order, and an error that lists what each one found.
#include "sim_app/data_dir.hpp"

#include <cstdlib>
#include <system_error>

namespace ocp::sim_app {
namespace {

namespace fs = std::filesystem;

bool holds(const fs::path& root, const std::string& relative) {
  std::error_code error;
  return fs::exists(root / relative, error);
}

// The build tree above `folder`: the nearest ancestor with a CMakeCache.txt (a test binary sits
// a few folders down, a program in bin/).
std::optional<fs::path> build_tree_above(fs::path folder) {
  std::error_code error;
  for (int depth = 0; depth < 8 && !folder.empty(); ++depth) {
    if (fs::is_regular_file(folder / "CMakeCache.txt", error)) return folder;
    if (folder == folder.parent_path()) break;
    folder = folder.parent_path();
  }
  return std::nullopt;
}

}  // namespace

DataSearch this_process_data_search() {
  DataSearch search;
  if (const char* value = std::getenv(data_override_variable)) search.override_dir = value;
  std::error_code error;
  search.executable = fs::read_symlink("/proc/self/exe", error);
  return search;
}

fs::path find_data(const std::string& relative, const DataSearch& search) {
  const std::string hint = std::string("set ") + data_override_variable +
                           " to the ocp-sim data folder (share/ocp-sim of the install, e.g. /usr/share/ocp-sim)";
  if (search.override_dir) {
    if (search.override_dir->empty()) {
      throw DataNotFound(std::string(data_override_variable) + " is set but empty; " + hint);
    }
    const fs::path root = *search.override_dir;
    if (holds(root, relative)) return root / relative;
    throw DataNotFound("cannot find the data '" + relative + "' in " + data_override_variable + "=" + root.string() +
                       " (looked for " + (root / relative).string() + "); " + hint);
  }
  std::vector<std::string> looked;
  if (!search.executable.empty()) {
    const fs::path bin = search.executable.parent_path();
    const fs::path installed = bin.parent_path() / "share" / "ocp-sim";
    if (holds(installed, relative)) return installed / relative;
    looked.push_back((installed / relative).string() + " (beside the executable " + search.executable.string() + ")");
    if (auto build = build_tree_above(bin)) {
      const fs::path staged = *build / "share" / "ocp-sim";
      if (holds(staged, relative)) return staged / relative;
      looked.push_back((staged / relative).string() + " (the build tree)");
    }
  } else {
    looked.push_back("nowhere beside the executable: /proc/self/exe is not readable");
  }
  std::string text = "cannot find the data '" + relative + "'; looked in";
  for (std::size_t i = 0; i < looked.size(); ++i) text += (i ? ", " : " ") + looked[i];
  text += "; " + std::string(data_override_variable) + " is not set: " + hint;
  throw DataNotFound(text);
}

fs::path find_data(const std::string& relative) { return find_data(relative, this_process_data_search()); }

}  // namespace ocp::sim_app
