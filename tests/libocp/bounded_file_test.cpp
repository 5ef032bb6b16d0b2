// The one bounded reader of every input file (ocp/bounded_file.hpp, issue #36): what is not a
// regular file is refused without blocking, a file over its kind's cap is refused before it is
// read, and the reason names the file and says why.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "ocp/bounded_file.hpp"

namespace ocp {
namespace {

namespace fs = std::filesystem;
using namespace std::string_literals;

class BoundedFileTest : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("ocp_bounded_file_" + std::to_string(getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    raise_file_caps(0);
    fs::remove_all(dir_);
  }
  std::string file(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name, std::ios::binary) << text;
    return (dir_ / name).string();
  }
  fs::path dir_;
};

constexpr FileKind small{"test file", 16, "--max-file-mb"};
constexpr FileKind fixed{"key file", 16};

struct Refused {
  const char* what;
  std::string path;
  const char* says;
};

TEST_F(BoundedFileTest, RefusesWhatIsNotARegularFileWithTheReason) {
  const std::string fifo = (dir_ / "fifo").string();
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  const Refused cases[] = {
      {"a FIFO (would block forever)", fifo, "a test file must be a regular file, not a FIFO"},
      {"an endless device", "/dev/zero", "a test file must be a regular file, not a character device"},
      {"a folder", dir_.string(), "a test file must be a regular file, not a folder"},
      {"a missing file", (dir_ / "missing").string(), "cannot open the test file: No such file or directory"},
      {"over the cap", file("big", std::string(17, 'x')), "17 bytes; a test file may be at most 16 bytes (raise with --max-file-mb)"},
  };
  for (const Refused& refused : cases) {
    const auto text = read_bounded_file(refused.path, small);
    ASSERT_FALSE(text.ok()) << refused.what;
    EXPECT_EQ(text.error().detail, refused.path + ": " + refused.says) << refused.what;
  }
}

TEST_F(BoundedFileTest, ReadsARegularFileUpToItsCap) {
  const std::string text(16, 'k');
  const auto read = read_bounded_file(file("ok", text), small);
  ASSERT_TRUE(read.ok()) << read.error().detail;
  EXPECT_EQ(*read, text);
  EXPECT_EQ(*read_bounded_file(file("empty", ""), small), "");
}

// A file whose size fstat does not know (procfs) is still read only up to the cap.
TEST_F(BoundedFileTest, AFileOfUnstatedSizeIsCutAtTheCap) {
  const auto read = read_bounded_file("/proc/self/maps", small);
  ASSERT_FALSE(read.ok());
  EXPECT_NE(read.error().detail.find("more than 16 bytes"), std::string::npos) << read.error().detail;
}

TEST_F(BoundedFileTest, TheFlagRaisesOnlyTheCapsThatNameIt) {
  const std::string big = file("big", std::string(100, 'x'));
  raise_file_caps(1000);
  EXPECT_TRUE(read_bounded_file(big, small).ok());
  const auto key = read_bounded_file(big, fixed);
  ASSERT_FALSE(key.ok());
  EXPECT_EQ(key.error().detail, big + ": 100 bytes; a key file may be at most 16 bytes");
}

TEST(EscapedExcerpt, IsShortOneLineAndEscaped) {
  EXPECT_EQ(escaped_excerpt("plain"), "plain");
  EXPECT_EQ(escaped_excerpt("a\nb\tc\\d\x1b[2J\x00z"s), "a\\nb\\tc\\\\d\\x1b[2J\\x00z");
  EXPECT_EQ(escaped_excerpt(std::string(200, 'y'), 10), std::string(10, 'y') + "…");
  EXPECT_EQ(escaped_excerpt("héllo"), "h\\xc3\\xa9llo");
}

}  // namespace
}  // namespace ocp
