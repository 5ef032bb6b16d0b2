// Where the programs find their data (sim_app/data_dir.hpp, issue 39): OCP_SIM_DATA, then
// beside the executable (../share/ocp-sim), then the build tree; and when none holds it, an
// error naming every place looked and the variable. Also the version every --version prints.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "ocp/build_info.hpp"
#include "sim_app/data_dir.hpp"
#include "scratch_dir.hpp"

namespace ocp::sim_app {
namespace {

namespace fs = std::filesystem;

class DataDir : public ::testing::Test {
 protected:
  fs::path file(const fs::path& relative) {
    const fs::path path = root_ / relative;
    fs::create_directories(path.parent_path());
    std::ofstream(path) << "x";
    return path;
  }
  // The error find_data throws, or "" when it finds the data.
  static std::string error_of(const std::string& relative, const DataSearch& search) {
    try {
      find_data(relative, search);
    } catch (const DataNotFound& missing) {
      return missing.what();
    }
    return "";
  }
  testing_support::ScratchDir scratch_{"ocp_data_dir_test"};
  fs::path root_ = scratch_.path();
};

TEST_F(DataDir, TheOverrideComesFirstAndAloneWhenSet) {
  file("override/web/index.html");
  file("prefix/share/ocp-sim/web/index.html");
  const DataSearch search{(root_ / "override").string(), root_ / "prefix/bin/player_sim"};
  EXPECT_EQ(find_data("web/index.html", search), root_ / "override/web/index.html");
  // Set but without the file: an error naming it, never the installed copy behind it.
  const std::string error = error_of("campaign/profiles", search);
  EXPECT_NE(error.find("OCP_SIM_DATA=" + (root_ / "override").string()), std::string::npos) << error;
  EXPECT_NE(error.find((root_ / "override/campaign/profiles").string()), std::string::npos) << error;
  EXPECT_NE(error_of("web/index.html", {std::string(), root_ / "prefix/bin/player_sim"}).find("OCP_SIM_DATA is set but empty"),
            std::string::npos);
}

TEST_F(DataDir, BesideTheExecutableThenTheBuildTree) {
  file("prefix/share/ocp-sim/web/index.html");
  EXPECT_EQ(find_data("web/index.html", {std::nullopt, root_ / "prefix/bin/player_sim"}),
            root_ / "prefix/share/ocp-sim/web/index.html");

  // A test binary a few folders down a build tree; the build tree's own data folder.
  file("build/CMakeCache.txt");
  file("build/share/ocp-sim/campaign/profiles/default.yaml");
  EXPECT_EQ(find_data("campaign/profiles", {std::nullopt, root_ / "build/tests/campaign/campaign_tests"}),
            root_ / "build/share/ocp-sim/campaign/profiles");
  // A program in build/bin finds it beside itself, the same rule as an install.
  EXPECT_EQ(find_data("campaign/profiles", {std::nullopt, root_ / "build/bin/ocp_campaign"}),
            root_ / "build/share/ocp-sim/campaign/profiles");
}

TEST_F(DataDir, MissingDataNamesEveryPlaceLookedAndTheVariable) {
  file("build/CMakeCache.txt");
  const std::string error = error_of("web/index.html", {std::nullopt, root_ / "build/tests/x/prog"});
  for (const fs::path& place : {root_ / "build/tests/share/ocp-sim/web/index.html", root_ / "build/share/ocp-sim/web/index.html"}) {
    EXPECT_NE(error.find(place.string()), std::string::npos) << place << "\n" << error;
  }
  EXPECT_NE(error.find("OCP_SIM_DATA"), std::string::npos) << error;
  EXPECT_NE(error_of("web", {std::nullopt, fs::path()}).find("/proc/self/exe is not readable"), std::string::npos);
  // Nothing above the executable is a build tree: only the installed place is named.
  const std::string installed_only = error_of("web", {std::nullopt, root_ / "elsewhere/bin/prog"});
  EXPECT_NE(installed_only.find((root_ / "elsewhere/share/ocp-sim/web").string()), std::string::npos) << installed_only;
  EXPECT_EQ(installed_only.find("build tree"), std::string::npos) << installed_only;
}

TEST(BuildInfo, VersionTextNamesTheBuildTheCompilerAndTheLibraries) {
  const std::string text = build_info::version_text("ocp_scenario");
  EXPECT_EQ(text.rfind("ocp_scenario (ocp-sim) " + std::string(build_info::version()) + "\n", 0), 0u) << text;
  EXPECT_FALSE(build_info::version().empty());
  EXPECT_FALSE(build_info::git_describe().empty());
  for (const char* word : {"build: git ", "compiler: ", "Boost 1.", "OpenSSL 3", "RapidJSON 1.", "yaml-cpp 0.", "spdlog ", "fmt "}) {
    EXPECT_NE(text.find(word), std::string::npos) << word << "\n" << text;
  }
  EXPECT_EQ(build_info::version_line(),
            std::string(build_info::version()) + " (git " + std::string(build_info::git_describe()) + ")");
}

}  // namespace
}  // namespace ocp::sim_app
