// Every numeric option of every executable (streamer_sim, player_sim, vehicle_client), through
// the very parse functions the programs call: NaN, infinities, empty values, negative values
// where they make no sense and out-of-range values are usage errors (exit code 2) with a clear
// message prefixed by the program's name. The built binaries are run for a few of them in
// executables_test.cpp.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "ocp/number_text.hpp"
#include "vehicle_app/options.hpp"
#include "player_app/player_cli.hpp"
#include "ocp/exit_codes.hpp"
#include "streamer_app/streamer_cli.hpp"

namespace ocp {
namespace {

enum class Program { streamer_sim, player_sim, vehicle_client };

const char* name(Program program) {
  switch (program) {
    case Program::streamer_sim: return "streamer_sim";
    case Program::player_sim: return "player_sim";
    case Program::vehicle_client: return "vehicle_client";
  }
  return "?";
}

struct Outcome {
  std::optional<int> exit_code;  // nullopt: would run
  std::string errors;            // stderr
};

Outcome parse(Program program, std::vector<std::string> words) {
  words.insert(words.begin(), name(program));
  std::vector<const char*> argv;
  for (const auto& word : words) argv.push_back(word.c_str());
  const int argc = static_cast<int>(argv.size());
  Outcome outcome;
  ::testing::internal::CaptureStderr();
  switch (program) {
    case Program::streamer_sim: {
      StreamerCli cli;
      outcome.exit_code = parse_streamer_cli(argc, argv.data(), cli);
      break;
    }
    case Program::player_sim: {
      PlayerCli cli;
      outcome.exit_code = parse_player_cli(argc, argv.data(), cli);
      break;
    }
    case Program::vehicle_client: {
      const ParseOutcome parsed = parse_program_options(argc, argv.data());
      if (!parsed.options) outcome.exit_code = parsed.exit_code;
      break;
    }
  }
  outcome.errors = ::testing::internal::GetCapturedStderr();
  return outcome;
}

struct NumericOption {
  Program program;
  std::vector<std::string> prefix;  // words before the value ("--plugin-param", "tcp_port")
  std::string good;                 // a value that must be accepted
  std::vector<std::string> bad;     // besides the values every numeric option rejects
};

const std::vector<std::string> never_numbers{"nan", "NaN", "-nan", "inf", "-inf", "infinity", "", "1e999", "12abc"};

std::vector<NumericOption> table() {
  std::vector<NumericOption> rows;
  for (const Program simulator : {Program::streamer_sim, Program::player_sim}) {
    rows.push_back({simulator, {"--link-delay-ms"}, "20.5", {"-1", "60001"}});
    rows.push_back({simulator, {"--link-jitter-ms"}, "5", {"-0.5", "60001"}});
    rows.push_back({simulator, {"--link-loss"}, "0.02", {"-0.1", "1.5"}});
    rows.push_back({simulator, {"--seed"}, "18446744073709551615", {"-1", "18446744073709551616", "1.5"}});
    rows.push_back({simulator, {"--duration-s"}, "0.5", {"-1", "1e8"}});
    rows.push_back({simulator, {"--ack-time-offset"}, "high", {"-1", "18446744073709551616", "1.5", "low"}});
    rows.push_back({simulator, {"--camera"}, "rear:15", {"rear:-1", "rear:0", "rear:1001"}});
    rows.push_back({simulator, {"--plugin-param", "tcp_port"}, "4100", {"-1", "65536"}});
    rows.push_back({simulator, {"--plugin-param", "ocp_player_tcp_port"}, "4101", {"-1", "65536"}});
    rows.push_back({simulator, {"--plugin-param", "latency_limit"}, "150", {"-1", "0", "3600001", "1.5"}});
  }
  rows.push_back({Program::streamer_sim, {"--operator-rate-hz"}, "50", {"-1", "0", "101"}});
  rows.push_back({Program::player_sim, {"--frame-rate-hz"}, "50", {"-1", "0", "101"}});
  const Program client = Program::vehicle_client;
  rows.push_back({client, {"--watchdog-ms"}, "300", {"-1", "0", "60001"}});
  rows.push_back({client, {"--max-throttle"}, "0.5", {"-0.1", "1.1"}});
  rows.push_back({client, {"--max-brake"}, "0.5", {"-0.1", "1.1"}});
  rows.push_back({client, {"--max-steer"}, "0.5", {"-0.1", "1.1"}});
  rows.push_back({client, {"--throttle-rate"}, "2", {"-1", "0", "1001"}});
  rows.push_back({client, {"--brake-rate"}, "2", {"-1", "0", "1001"}});
  rows.push_back({client, {"--steer-rate"}, "2", {"-1", "0", "1001"}});
  rows.push_back({client, {"--safe-brake"}, "0.5", {"-0.1", "1.1"}});
  rows.push_back({client, {"--start-lat"}, "-45", {"-90", "90"}});
  rows.push_back({client, {"--start-lon"}, "-120", {"-181", "181"}});
  rows.push_back({client, {"--start-heading-deg"}, "-90", {"-361", "361"}});
  rows.push_back({client, {"--wheelbase-m"}, "3", {"-1", "0", "51"}});
  rows.push_back({client, {"--max-steer-rad"}, "0.5", {"-1", "0", "1.6"}});
  rows.push_back({client, {"--max-speed-mps"}, "10", {"-1", "0", "101"}});
  rows.push_back({client, {"--response-period-ms"}, "10", {"-1", "0", "1001"}});
  rows.push_back({client, {"--connect-timeout-ms"}, "500", {"-1", "0", "600001"}});
  rows.push_back({client, {"--duration-s"}, "0.5", {"-1", "0", "1e8"}});
  rows.push_back({client, {"--misbehave-delay-responses-ms"}, "5", {"-1", "60001"}});
  return rows;
}

std::string describe(const NumericOption& row, const std::string& value) {
  std::string text = name(row.program);
  for (const auto& word : row.prefix) text += " " + word;
  return text + " '" + value + "'";
}

TEST(NumericOptions, EveryNumericOptionAcceptsAGoodValue) {
  for (const NumericOption& row : table()) {
    std::vector<std::string> words = row.prefix;
    words.push_back(row.good);
    const Outcome outcome = parse(row.program, words);
    EXPECT_FALSE(outcome.exit_code.has_value()) << describe(row, row.good) << ": " << outcome.errors;
  }
}

TEST(NumericOptions, EveryNumericOptionRejectsNonNumbersNegativesAndOutOfRange) {
  std::size_t checked = 0;
  for (const NumericOption& row : table()) {
    std::vector<std::string> values = never_numbers;
    values.insert(values.end(), row.bad.begin(), row.bad.end());
    for (const std::string& value : values) {
      std::vector<std::string> words = row.prefix;
      // --camera and --plugin-param take the number inside their own text.
      words.push_back(row.prefix[0] == "--camera" ? "rear:" + value : value);
      if (row.prefix[0] == "--camera" && value.starts_with("rear:")) words.back() = value;
      const Outcome outcome = parse(row.program, words);
      ASSERT_TRUE(outcome.exit_code.has_value()) << describe(row, value) << " was accepted";
      EXPECT_EQ(*outcome.exit_code, ocp::cli::exit_usage_error) << describe(row, value);
      EXPECT_TRUE(outcome.errors.starts_with(std::string(name(row.program)) + ": "))
          << describe(row, value) << ": " << outcome.errors;
      // CLI11 takes "-inf" after a NAME of --plugin-param (which may stand alone) for an
      // option of its own, and says so: "The following argument was not expected: -inf".
      const bool read_as_option = row.prefix.size() == 2 && value.starts_with("-") && !parse_finite_number(value);
      if (!read_as_option) {
        EXPECT_NE(outcome.errors.find(row.prefix.back()), std::string::npos)
            << describe(row, value) << " does not name the option: " << outcome.errors;
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 400u);
}

TEST(NumericOptions, AckTimeOffsetHighIsFarAbove2To53) {
  StreamerCli cli;
  const char* argv[] = {"streamer_sim", "--ack-time-offset", "high"};
  ::testing::internal::CaptureStderr();
  EXPECT_FALSE(parse_streamer_cli(3, argv, cli).has_value());
  ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(cli.simulation_options().ack_time_offset, (std::uint64_t{1} << 62) + 12345);
  PlayerCli player;
  const char* player_argv[] = {"player_sim", "--ack-time-offset", "18446744073709551615"};
  ::testing::internal::CaptureStderr();
  EXPECT_FALSE(parse_player_cli(3, player_argv, player).has_value());
  ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(player.simulation_options().ack_time_offset, 18446744073709551615ULL);
}

TEST(CommandLine, VehicleClientErrorsCarryTheProgramName) {
  for (const std::vector<std::string>& words :
       std::vector<std::vector<std::string>>{{"--no-such-option"}, {"--watchdog-ms"}, {"localhost:99999"}}) {
    const Outcome outcome = parse(Program::vehicle_client, words);
    ASSERT_TRUE(outcome.exit_code.has_value());
    EXPECT_EQ(*outcome.exit_code, 2);
    EXPECT_TRUE(outcome.errors.starts_with("vehicle_client: ")) << outcome.errors;
  }
}

TEST(CommandLine, TheOtherSimulatorsPortParameterIsWarnedAbout) {
  const Outcome player = parse(Program::player_sim, {"--plugin-param", "tcp_port", "4550"});
  EXPECT_FALSE(player.exit_code.has_value());
  EXPECT_NE(player.errors.find("player_sim: warning: --plugin-param tcp_port has no effect in player_sim: it sets "
                               "the vehicle API port of streamer_sim"),
            std::string::npos)
      << player.errors;
  const Outcome streamer = parse(Program::streamer_sim, {"--plugin-param", "ocp_player_tcp_port", "4551"});
  EXPECT_NE(streamer.errors.find("--plugin-param ocp_player_tcp_port has no effect in streamer_sim"),
            std::string::npos)
      << streamer.errors;
  // Parameters that act in both say nothing.
  const Outcome quiet = parse(Program::player_sim, {"--plugin-param", "ocp_player_tcp_port", "4551", "--plugin-param",
                                                    "latency_limit", "150", "--plugin-param", "ocp_tcp_allow_remote"});
  EXPECT_EQ(quiet.errors, "");
}

}  // namespace
}  // namespace ocp
