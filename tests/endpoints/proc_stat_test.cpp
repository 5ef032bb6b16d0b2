// sim_app/proc_stat.hpp: the fields of a /proc/PID/stat line after the command name, which may
// hold spaces and ')', and the bounded read of a small /proc file.
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <string>
#include <vector>

#include "scratch_dir.hpp"
#include "sim_app/proc_stat.hpp"

namespace ocp::sim_app {
namespace {

struct StatCase {
  const char* name;
  std::string text;
  std::vector<std::string> fields;
};

TEST(ProcStat, FieldsAfterTheCommandName) {
  const std::vector<StatCase> cases = {
      {"a normal line", "1234 (sh) S 1 1234 1234 0 -1 4194560 99 0 0 0 7 3 0 0 20 0 1\n",
       {"S", "1", "1234", "1234", "0", "-1", "4194560", "99", "0", "0", "0", "7", "3", "0", "0", "20", "0", "1\n"}},
      {"a name with spaces and ')'", "42 (a) b (c)) R 7 42\n", {"R", "7", "42\n"}},
      {"a name that looks like fields", "42 () S 1 2 3) Z 9 10\n", {"Z", "9", "10\n"}},
      {"a name with a newline", "42 (two\nlines) S 1\n", {"S", "1\n"}},
      {"a line cut in a field", "1234 (sh) S 1 1234 12", {"S", "1", "1234", "12"}},
      {"a line cut after a space", "1234 (sh) S 1 ", {"S", "1"}},
      {"a line cut after the name", "1234 (sh)", {}},
      {"a line cut in the name", "1234 (sh", {}},
      {"empty text", "", {}},
      {"no name at all", "1234 S 1 2 3", {}},
  };
  for (const StatCase& each : cases) EXPECT_EQ(stat_fields(each.text), each.fields) << each.name;
}

TEST(ProcStat, ReadsThisProcesssStat) {
  const std::vector<std::string> fields = stat_fields(read_small_proc_file("/proc/self/stat"));
  ASSERT_GE(fields.size(), 15U);
  EXPECT_EQ(fields[0], "R");   // this thread is running while it reads
  EXPECT_EQ(std::stol(fields[2]), static_cast<long>(getpgrp()));
}

TEST(ProcStat, ReadsAtMostTheBoundAndNothingFromWhatIsMissing) {
  const testing_support::ScratchDir scratch("proc_stat");
  const std::string path = (scratch.path() / "large").string();
  std::ofstream(path) << std::string(5000, 'x');
  EXPECT_EQ(read_small_proc_file(path.c_str()), std::string(1023, 'x'));
  EXPECT_EQ(read_small_proc_file(path.c_str(), 2047), std::string(2047, 'x'));
  EXPECT_EQ(read_small_proc_file((scratch.path() / "missing").string().c_str()), "");
  EXPECT_EQ(read_small_proc_file(scratch.path().string().c_str()), "");   // a folder reads nothing
}

}  // namespace
}  // namespace ocp::sim_app
