// The command line both simulator executables share (sim_common): --plugin-param exactly as
// the product spells it, link impairments, cameras, log level, and the built-in gamepad script.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <vector>

#include "sim_app/common_options.hpp"
#include "ocp/exit_codes.hpp"
#include "sim_app/gamepad_script.hpp"
#include "ocp/delivery_trace.hpp"

namespace ocp::sim_app {
namespace {

struct Parsed {
  std::optional<int> exit_code;
  CommonOptions options;
};

Parsed parse(std::vector<const char*> arguments) {
  arguments.insert(arguments.begin(), "sim");
  CLI::App app{"test", "sim"};
  Parsed parsed;
  add_common_options(app, parsed.options);
  parsed.exit_code = parse_command_line(app, static_cast<int>(arguments.size()), arguments.data(), parsed.options);
  return parsed;
}

TEST(CommonOptions, DefaultsRunWithTheProductSettings) {
  const Parsed parsed = parse({});
  ASSERT_FALSE(parsed.exit_code.has_value());
  EXPECT_EQ(parsed.options.plugin_params.tcp_port, 4000);
  EXPECT_EQ(parsed.options.plugin_params.ocp_player_tcp_port, 4001);
  EXPECT_FALSE(parsed.options.plugin_params.ocp_tcp_allow_remote);
  EXPECT_EQ(parsed.options.log_level, LogLevel::info);
  EXPECT_FALSE(parsed.options.duration().has_value());
  EXPECT_TRUE(parsed.options.cameras.empty());
}

TEST(CommonOptions, PluginParamsAreRepeatableNameValuePairs) {
  const Parsed parsed = parse({"--plugin-param", "tcp_port", "4100", "--plugin-param", "latency_limit", "250",
                               "--plugin-param", "ocp_tcp_allow_remote", "1"});
  ASSERT_FALSE(parsed.exit_code.has_value());
  EXPECT_EQ(parsed.options.plugin_params.tcp_port, 4100);
  EXPECT_EQ(parsed.options.plugin_params.latency_limit, Millis{250});
  EXPECT_TRUE(parsed.options.plugin_params.ocp_tcp_allow_remote);
}

TEST(CommonOptions, AllowRemoteMayBeGivenWithoutAValue) {
  const Parsed parsed = parse({"--plugin-param", "ocp_tcp_allow_remote", "--seed", "7"});
  ASSERT_FALSE(parsed.exit_code.has_value());
  EXPECT_TRUE(parsed.options.plugin_params.ocp_tcp_allow_remote);
  EXPECT_EQ(parsed.options.seed, 7u);
}

TEST(CommonOptions, UsageErrorsExitWithCodeTwo) {
  const std::vector<std::vector<const char*>> bad = {
      {"--plugin-param", "tcp_port"},                 // value missing
      {"--plugin-param", "tcp_port", "4000", "x"},    // one word too many
      {"--plugin-param", "tcp_port", "99999"},
      {"--plugin-param", "no_such_param", "1"},
      {"--link-loss", "2"},
      {"--link-delay-ms", "-1"},
      {"--log-level", "loud"},
      {"--camera", "front:0"},
      {"--camera", "front", "--camera", "front"},
      {"--unknown"},
  };
  for (const auto& arguments : bad) {
    const Parsed parsed = parse(arguments);
    ASSERT_TRUE(parsed.exit_code.has_value()) << arguments[0];
    EXPECT_EQ(*parsed.exit_code, ocp::cli::exit_usage_error) << arguments[0];
  }
}

TEST(CommonOptions, HelpExitsWithCodeZero) {
  const Parsed parsed = parse({"--help"});
  ASSERT_TRUE(parsed.exit_code.has_value());
  EXPECT_EQ(*parsed.exit_code, ocp::cli::exit_ok);
}

TEST(CommonOptions, LinkOptionsBecomeImpairmentsInMicroseconds) {
  const Parsed parsed = parse({"--link-delay-ms", "12.5", "--link-jitter-ms", "3", "--link-loss", "0.25",
                               "--duration-s", "1.5"});
  ASSERT_FALSE(parsed.exit_code.has_value());
  const Impairments impairments = parsed.options.link_impairments();
  EXPECT_EQ(impairments.delay, Micros{12'500});
  EXPECT_EQ(impairments.jitter_kind, Impairments::JitterKind::uniform);
  EXPECT_EQ(impairments.jitter, Micros{3'000});
  EXPECT_DOUBLE_EQ(impairments.loss_probability, 0.25);
  EXPECT_EQ(parsed.options.duration(), Micros{1'500'000});
}

TEST(CommonOptions, LinkTracesLoadPerDirection) {
  const auto path = std::filesystem::temp_directory_path() / "ocp_common_options_up.trace";
  std::ofstream(path) << "1\n1\n2\n";
  const Parsed parsed = parse({"--link-trace-up", path.c_str(), "--link-queue-packets", "64"});
  std::filesystem::remove(path);
  ASSERT_FALSE(parsed.exit_code.has_value());
  const SimulatedWorldOptions world = parsed.options.world_options();
  ASSERT_TRUE(world.to_player().trace);   // up: the vehicle's uplink
  EXPECT_EQ(world.to_player().trace->opportunities_per_period(), 3u);
  EXPECT_EQ(world.to_player().queue_limit_packets, 64u);
  EXPECT_FALSE(world.to_streamer().trace);
}

TEST(CommonOptions, BadLinkTracesAreUsageErrors) {
  const auto path = std::filesystem::temp_directory_path() / "ocp_common_options_bad.trace";
  std::ofstream(path) << "4\nsoon\n";
  const Parsed bad = parse({"--link-trace-down", path.c_str()});
  std::filesystem::remove(path);
  ASSERT_TRUE(bad.exit_code.has_value());
  EXPECT_EQ(*bad.exit_code, ocp::cli::exit_usage_error);
  const Parsed missing = parse({"--link-trace-up", "/nonexistent/up.trace"});
  ASSERT_TRUE(missing.exit_code.has_value());
  EXPECT_EQ(*missing.exit_code, ocp::cli::exit_usage_error);
}

TEST(CommonOptions, CamerasTakeAnOptionalFrameRate) {
  const Parsed parsed = parse({"--camera", "front", "--camera", "rear:15"});
  ASSERT_FALSE(parsed.exit_code.has_value());
  ASSERT_EQ(parsed.options.cameras.size(), 2u);
  EXPECT_EQ(parsed.options.cameras[0].name, "front");
  EXPECT_DOUBLE_EQ(parsed.options.cameras[0].fps, 30.0);
  EXPECT_EQ(parsed.options.cameras[1].name, "rear");
  EXPECT_DOUBLE_EQ(parsed.options.cameras[1].fps, 15.0);
}

TEST(GamepadScript, DrivePressesStartAloneThenDrives) {
  const auto script = parse_gamepad_script("drive");
  ASSERT_TRUE(script.ok());
  Gamepad gamepad;
  apply_gamepad_script(gamepad, *script, SimTime{0});
  const auto pressed = gamepad.sample(Millis{100});
  ASSERT_TRUE(pressed.has_value());
  EXPECT_TRUE(pressed->buttons.start);
  EXPECT_EQ(pressed->axes, Axes{});           // neutral sticks: the interlock may enable
  const auto driving = gamepad.sample(Millis{1000});
  ASSERT_TRUE(driving.has_value());
  EXPECT_FALSE(driving->buttons.start);
  EXPECT_GT(driving->axes.right_trigger, -1.0);
  // It loops: the start press comes again for a vehicle that connected late.
  EXPECT_TRUE(gamepad.sample(Millis{3100})->buttons.start);
}

TEST(GamepadScript, IdleIsNeutralAndAMissingFileIsAnError) {
  const auto idle = parse_gamepad_script("idle");
  ASSERT_TRUE(idle.ok());
  Gamepad gamepad;
  apply_gamepad_script(gamepad, *idle, SimTime{0});
  EXPECT_TRUE(gamepad.sample(Millis{500})->is_safe_default());
  const auto missing = parse_gamepad_script("/nonexistent/recording.txt");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().detail.find("--gamepad '/nonexistent/recording.txt'"), std::string::npos);
}

}  // namespace
}  // namespace ocp::sim_app
