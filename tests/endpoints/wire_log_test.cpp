// --wire-log: one JSON line per frame in each direction, written from the event stream.
#include <gtest/gtest.h>
#include <rapidjson/document.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "ocp/virtual_executor.hpp"
#include "sim_app/wire_log.hpp"
#include "world/world.hpp"

namespace ocp {
namespace {

WorldConfig one_vehicle() {
  WorldConfig config;
  config.deterministic_keys = true;
  VehicleSpec vehicle;
  vehicle.name = "truck-1";
  config.vehicles.push_back(vehicle);
  return config;
}

std::vector<std::string> read_lines(const std::string& path) {
  std::ifstream file(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(file, line);) lines.push_back(line);
  return lines;
}

std::string temp_path(const char* name) {
  return (std::filesystem::temp_directory_path() / (std::string(name) + std::to_string(::getpid()))).string();
}

TEST(WireLog, WritesEveryFrameInBothDirectionsAsJsonLines) {
  const std::string path = temp_path("ocp_wire_log_");
  VirtualExecutor executor;
  World world(executor, one_vehicle(), make_null_sink());
  auto log = sim_app::WireLog::open(path, world.events(), Logger(executor, "test", make_null_sink()));
  ASSERT_TRUE(log) << log.error().detail;
  ASSERT_TRUE(world.start());
  executor.run_for(Millis{100});
  const StreamerStats& stats = world.streamer("truck-1").stats();
  const std::uint64_t frames = stats.control_frames_sent + stats.vehicle_responses_received;
  world.stop();
  log->reset();   // flushes and closes the file

  const auto lines = read_lines(path);
  std::filesystem::remove(path);
  ASSERT_EQ(lines.size(), frames);
  std::size_t out = 0;
  std::size_t in = 0;
  for (const std::string& line : lines) {
    rapidjson::Document document;
    document.Parse(line.c_str());
    ASSERT_FALSE(document.HasParseError()) << line;
    EXPECT_STREQ(document["event"].GetString(), "frame");
    EXPECT_TRUE(document["t_us"].IsInt64());
    EXPECT_TRUE(document["len"].IsUint());
    EXPECT_EQ(document["len"].GetUint(), document["payload"].GetStringLength()) << line;
    EXPECT_TRUE(document["ack_time"].IsUint64()) << line;
    (std::string(document["dir"].GetString()) == "out" ? out : in) += 1;
  }
  EXPECT_EQ(out, stats.control_frames_sent);
  EXPECT_EQ(in, stats.vehicle_responses_received);
  EXPECT_GT(in, 5u);
}

TEST(WireLog, StopsAtItsLimitAndSaysSo) {
  const std::string path = temp_path("ocp_wire_log_cap_");
  VirtualExecutor executor;
  World world(executor, one_vehicle(), make_null_sink());
  auto log = sim_app::WireLog::open(path, world.events(), Logger(executor, "test", make_null_sink()),
                                /*max_bytes=*/4096);
  ASSERT_TRUE(log);
  ASSERT_TRUE(world.start());
  executor.run_for(Millis{1000});
  world.stop();
  log->reset();
  const auto lines = read_lines(path);
  std::uintmax_t size = std::filesystem::file_size(path);
  std::filesystem::remove(path);
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines.back(), R"({"event":"wire_log_full"})");
  EXPECT_LE(size, 4096u + lines.back().size() + 1);
}

TEST(WireLog, AnUnwritablePathIsAClearError) {
  VirtualExecutor executor;
  World world(executor, one_vehicle(), make_null_sink());
  auto log = sim_app::WireLog::open("/nonexistent-dir/wire.jsonl", world.events(),
                                Logger(executor, "test", make_null_sink()));
  ASSERT_FALSE(log);
  EXPECT_NE(log.error().detail.find("cannot write '/nonexistent-dir/wire.jsonl'"), std::string::npos)
      << log.error().detail;
}

}  // namespace
}  // namespace ocp
