// build_info.hpp. The version and the compiler come from CMake as definitions; the git
// describe from a file the build rewrites only when it changes (git_describe.cmake), so a new
// commit recompiles this one file.
#include "ocp/build_info.hpp"

#include <boost/version.hpp>
#include <fmt/core.h>
#include <openssl/crypto.h>
#include <rapidjson/rapidjson.h>
#include <spdlog/version.h>

#include "ocp_git_describe.inc"   // defines OCP_GIT_DESCRIBE

namespace ocp::build_info {
namespace {

std::string boost_version() {
  return std::to_string(BOOST_VERSION / 100000) + "." + std::to_string(BOOST_VERSION / 100 % 1000) + "." +
         std::to_string(BOOST_VERSION % 100);
}

}  // namespace

std::string_view version() { return OCP_VERSION; }
std::string_view git_describe() { return OCP_GIT_DESCRIBE; }
std::string_view compiler() { return OCP_COMPILER; }

std::string version_line() { return std::string(version()) + " (git " + std::string(git_describe()) + ")"; }

std::vector<std::pair<std::string, std::string>> libraries() {
  return {
      {"Boost", boost_version()},
      {"OpenSSL", OpenSSL_version(OPENSSL_VERSION_STRING)},   // the linked library, e.g. "3.0.19"
      {"RapidJSON", RAPIDJSON_VERSION_STRING},
      {"yaml-cpp", OCP_YAML_CPP_VERSION},
      {"spdlog", std::to_string(SPDLOG_VER_MAJOR) + "." + std::to_string(SPDLOG_VER_MINOR) + "." +
                     std::to_string(SPDLOG_VER_PATCH)},
      {"fmt", std::to_string(FMT_VERSION / 10000) + "." + std::to_string(FMT_VERSION / 100 % 100) + "." +
                  std::to_string(FMT_VERSION % 100)},
  };
}

std::string version_text(std::string_view program) {
  std::string text = std::string(program) + " (ocp-sim) " + std::string(version()) + "\n";
  text += "build: git " + std::string(git_describe()) + "\n";
  text += "compiler: " + std::string(compiler()) + "\n";
  text += "libraries:";
  bool first = true;
  for (const auto& [name, library_version] : libraries()) {
    text += (first ? " " : ", ") + name + " " + library_version;
    first = false;
  }
  return text;
}

}  // namespace ocp::build_info
