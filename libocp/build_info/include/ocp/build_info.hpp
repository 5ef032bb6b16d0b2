#pragma once
// What built this program (issue 39): the project's version (CMakeLists.txt's project(VERSION),
// the one place), the build's `git describe`, the compiler and the libraries' versions. Printed
// by every executable's --version and recorded in the reports, so a certificate names the tool
// that gave it.
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace ocp::build_info {

std::string_view version();        // "0.1.0"
std::string_view git_describe();   // `git describe --always --dirty` of the build, or "unknown"
std::string_view compiler();       // "GNU 12.2.0"

// One line for reports: "0.1.0 (git v0.1.0-3-gabc1234)".
std::string version_line();

// (library, version): Boost, OpenSSL (the one linked, at run time), RapidJSON, yaml-cpp, spdlog, fmt.
std::vector<std::pair<std::string, std::string>> libraries();

// The --version text of `program`: its name and version, then the build, the compiler and the libraries.
std::string version_text(std::string_view program);

}  // namespace ocp::build_info
