#pragma once
// CLI11 validators for the files and folders a tool writes, so that a path that cannot be
// written is a usage error (exit 2) when the command line is read, not after a run of minutes:
//   app.add_option("--json", path)->check(ocp::cli::writable_file());
//   app.add_option("--out", folder)->check(ocp::cli::writable_folder());
// Nothing is created here; the tool makes its folder when it writes.
#include <CLI/CLI.hpp>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>

namespace ocp::cli {

namespace detail {

// The deepest folder of `path` that exists ("." for a relative path with none).
inline std::filesystem::path existing_ancestor(std::filesystem::path path) {
  std::error_code ignored;
  while (!path.empty() && !std::filesystem::exists(path, ignored)) path = path.parent_path();
  return path.empty() ? std::filesystem::path(".") : path;
}

// "" when files can be made in `folder` (or below it, once its missing parts are made).
inline std::string folder_problem(const std::filesystem::path& wanted) {
  const std::filesystem::path folder = existing_ancestor(wanted);
  std::error_code ignored;
  if (!std::filesystem::is_directory(folder, ignored)) return "'" + folder.string() + "' is not a folder";
  if (::access(folder.c_str(), W_OK | X_OK) != 0) {
    return "cannot write in '" + folder.string() + "': " + std::strerror(errno);
  }
  return "";
}

}  // namespace detail

inline CLI::Validator writable_file() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        if (text.empty()) return "expected a file name, got ''";
        if (text == "-") return "";   // standard output or error, where a tool takes it
        const std::filesystem::path path(text);
        std::error_code ignored;
        if (std::filesystem::is_directory(path, ignored)) return "'" + text + "' is a folder, expected a file";
        if (std::filesystem::exists(path, ignored)) {
          return ::access(path.c_str(), W_OK) == 0 ? "" : "cannot write '" + text + "': " + std::strerror(errno);
        }
        const std::filesystem::path parent = path.parent_path().empty() ? "." : path.parent_path();
        if (!std::filesystem::is_directory(parent, ignored)) return "folder '" + parent.string() + "' does not exist";
        return detail::folder_problem(parent);
      },
      "FILE");
}

inline CLI::Validator writable_folder() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        if (text.empty()) return "expected a folder name, got ''";
        return detail::folder_problem(std::filesystem::path(text));
      },
      "DIR");
}

}  // namespace ocp::cli
