// The app layer's loaders (sim_app/file_loaders.hpp): the file is read by the bounded reader
// and parsed by the sans-IO parser; a parse error and a missing file both name the file.
#include "sim_app/file_loaders.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>

#include "scratch_dir.hpp"

namespace ocp::sim_app {
namespace {

using namespace std::chrono_literals;
using testing_support::ScratchDir;

std::string write_file(const ScratchDir& folder, const std::string& name, const std::string& text) {
  const std::string path = (folder / name).string();
  std::ofstream(path) << text;
  return path;
}

TEST(FileLoaders, DeliveryTraceParsedAndNamedWhenBadOrMissing) {
  const ScratchDir folder("ocp_file_loaders");
  const std::string bad_path = write_file(folder, "bad.trace", "4\n8\nx\n");
  const auto bad = load_delivery_trace(bad_path);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().detail, bad_path + ":3: expected a whole number of milliseconds, got 'x'");
  const auto good = load_delivery_trace(write_file(folder, "good.trace", "4\n8\n"));
  ASSERT_TRUE(good.ok());
  EXPECT_EQ(good->period(), 8ms);
  const auto missing = load_delivery_trace("/nonexistent/drive.trace");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().detail, "/nonexistent/drive.trace: cannot open the delivery trace: No such file or directory");
}

TEST(FileLoaders, LinkRecordingParsedAndNamedWhenMissing) {
  const ScratchDir folder("ocp_file_loaders");
  const auto good = load_link_recording(write_file(folder, "drive.link", "ocp-link-recording 1\nto_player 0 1000\n"));
  ASSERT_TRUE(good.ok()) << good.error().detail;
  EXPECT_EQ(good->route(LinkRoute::to_player).size(), 1u);
  const auto missing = load_link_recording("/nonexistent/drive.link");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().detail, "/nonexistent/drive.link: cannot open the link recording: No such file or directory");
}

TEST(FileLoaders, GamepadRecordingParsedAndRefusedWhenMissing) {
  const ScratchDir folder("ocp_file_loaders");
  const auto loaded = load_gamepad_recording(write_file(folder, "drive.txt", "0 left_x=0.5\n20 a=1\n"));
  ASSERT_TRUE(loaded.ok()) << loaded.error().detail;
  ASSERT_EQ(loaded->states.size(), 2u);
  EXPECT_EQ(loaded->states[0].controller.axes.left_x, 0.5);
  EXPECT_TRUE(loaded->states[1].controller.buttons.a);
  const auto missing = load_gamepad_recording((folder / "missing.txt").string());
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().detail.find("cannot open the gamepad script"), std::string::npos);
}

}  // namespace
}  // namespace ocp::sim_app
