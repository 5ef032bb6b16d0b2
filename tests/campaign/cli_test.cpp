// ocp_campaign's command line (issue #21): every option has a range, a bad value or a bad
// profile is a clear error and exit 2; a profile error says file:line:column.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "campaign/profile.hpp"
#include "child_process.hpp"

namespace ocp::campaign {
namespace {

struct Ran {
  int code = -1;
  std::string output;
};

Ran run(const std::string& arguments) {
  const ocp::test::CommandRun command = ocp::test::run_command(std::string(OCP_CAMPAIGN_PATH) + " " + arguments);
  return Ran{command.exit_code, command.output};
}

struct BadArguments {
  const char* arguments;
  const char* says;
};

TEST(CampaignCli, BadValuesExitTwo) {
  const BadArguments cases[] = {
      {"run --worlds 0", "--worlds"},
      {"run --worlds many", "--worlds"},
      {"run -j 0", "--jobs"},
      {"run -j 1000", "--jobs"},
      {"run --seed -1", "--seed"},
      {"run --shard 4/4", "--shard"},
      {"run --shard 1", "--shard"},
      {"run --shard 0/0", "--shard"},
      {"run --profile nonexistent", "cannot open the campaign profile: No such file or directory"},
      {"run --worlds 5 --world 5", "--world"},
      {"run --shrink-runs 0", "--shrink-runs"},
      {"run --max-world-seconds 0", "--max-world-seconds"},
      {"run --max-world-seconds nan", "--max-world-seconds"},
      // The ceiling on events per simulated second (issue #36): run and check take it.
      {"run --max-events-per-s 0", "--max-events-per-s"},
      {"run --max-events-per-s -1", "--max-events-per-s"},
      {"run --max-events-per-s nan", "--max-events-per-s"},
      {"run --max-events-per-s inf", "--max-events-per-s"},
      {"run --max-events-per-s 1500.5", "--max-events-per-s"},
      {"run --max-events-per-s ''", "--max-events-per-s"},
      {"run --max-events-per-s 999", "--max-events-per-s"},
      {"run --max-events-per-s 18446744073709551616", "--max-events-per-s"},
      {"check x.yaml --max-events-per-s 0", "--max-events-per-s"},
      {"check x.yaml --max-events-per-s many", "--max-events-per-s"},
      {"check x.yaml --max-events-per-s 1e30", "--max-events-per-s"},
      {"run --client ''", "--client: empty command"},
      {"run --client 'no-such-vehicle-client {port}'", "cannot run 'no-such-vehicle-client': not found in PATH"},
      {"merge /nonexistent-dir", "/nonexistent-dir: cannot open the campaign summary: No such file or directory"},
      {"check /nonexistent.yaml", "/nonexistent.yaml: cannot open the scenario file"},
      {"slurm --tasks 0", "--tasks"},
      {"slurm --poll 0", "--poll"},
      {"frobnicate", ""},
  };
  for (const BadArguments& bad : cases) {
    const Ran ran = run(bad.arguments);
    EXPECT_EQ(ran.code, 2) << bad.arguments << "\n" << ran.output;
    EXPECT_NE(ran.output.find(bad.says), std::string::npos) << bad.arguments << "\n" << ran.output;
  }
}

TEST(CampaignCli, HelpOnEverySubcommand) {
  for (const char* command : {"--help", "run --help", "check --help", "merge --help", "slurm --help"}) {
    const Ran ran = run(command);
    EXPECT_EQ(ran.code, 0) << command;
    EXPECT_NE(ran.output.find("Usage"), std::string::npos) << command;
  }
}

TEST(CampaignCli, SlurmPrintOnlyWritesAnArrayScript) {
  const Ran ran = run("slurm --print-only --seed 5 --worlds 200 --tasks 4 --out /tmp/x");
  EXPECT_EQ(ran.code, 0) << ran.output;
  EXPECT_NE(ran.output.find("#SBATCH --array=0-3"), std::string::npos) << ran.output;
  EXPECT_NE(ran.output.find("run --seed 5 --worlds 200"), std::string::npos) << ran.output;
  // The shard from the array's environment, the binary and the results by absolute path.
  EXPECT_NE(ran.output.find("--shard \"$SLURM_ARRAY_TASK_ID/4\""), std::string::npos) << ran.output;
  EXPECT_NE(ran.output.find("exec '/"), std::string::npos) << ran.output;
  EXPECT_NE(ran.output.find("--out '/tmp/x'/shard-\"$SLURM_ARRAY_TASK_ID\""), std::string::npos) << ran.output;
  const Ran file = run("slurm --print-only --profile my/p.yaml --out rel");
  EXPECT_NE(file.output.find("--profile '/"), std::string::npos) << file.output;
  EXPECT_EQ(file.output.find("--out 'rel'"), std::string::npos) << file.output;
  // What run takes about the client goes to every task as given.
  const Ran client = run("slurm --print-only --client 'my_client 127.0.0.1:{port}' --time real --max-world-seconds 5 "
                         "--max-events-per-s 2000000 --out /tmp/x");
  EXPECT_EQ(client.code, 0) << client.output;
  EXPECT_NE(client.output.find("--client 'my_client 127.0.0.1:{port}' --time real --max-world-seconds 5 "
                               "--max-events-per-s 2000000\n"),
            std::string::npos)
      << client.output;
}

TEST(CampaignCli, SlurmWithoutSbatchNamesItAndExitsTwo) {
  const std::string out = ::testing::TempDir() + "ocp-campaign-no-sbatch";
  // PATH without Slurm: the tool must say which command is missing (/bin/sh is absolute).
  const ocp::test::CommandRun bare = ocp::test::run_command("PATH=/nonexistent " + std::string(OCP_CAMPAIGN_PATH) +
                                                  " slurm --profile calm --worlds 4 --out " + out);
  EXPECT_EQ(bare.exit_code, 2) << bare.output;
  EXPECT_NE(bare.output.find("'sbatch' is not on PATH"), std::string::npos) << bare.output;
}

struct BadProfile {
  const char* text;
  const char* position;
  const char* says;
};

TEST(CampaignProfile, MistakesSayWhereAndWhy) {
  const BadProfile cases[] = {
      {"duration: [10s, 5s]\n", ":1:11:", "min > max"},
      {"vehicles: [0, 4]\n", ":1:11:", "out of range"},
      {"colour: red\n", ":1:1:", "unknown key 'colour'"},
      {"timers:\n  latency_limit: [1ms, 1s]\n", ":2:18:", "out of range"},
      {"weights:\n  impair: -1\n", ":2:11:", "weight out of range"},
      {"weights:\n  teleport: 1\n", ":2:3:", "unknown key 'teleport'"},
      {"monitor_share: 2\n", ":1:16:", "[0, 1]"},
      {"duration: [10s\n", ":", "end of sequence"},
      {"link:\n  delay: [0ms, soon]\n", ":2:16:", "duration"},
  };
  for (const BadProfile& bad : cases) {
    try {
      parse_profile(bad.text, "p.yaml");
      ADD_FAILURE() << "accepted: " << bad.text;
    } catch (const ProfileError& error) {
      const std::string message = error.what();
      EXPECT_EQ(message.rfind("p.yaml", 0), 0u) << message;
      EXPECT_NE(message.find(bad.position), std::string::npos) << bad.text << " → " << message;
      EXPECT_NE(message.find(bad.says), std::string::npos) << bad.text << " → " << message;
    }
  }
  // Through the tool: exit 2, the position on the line.
  const std::string path = testing::TempDir() + "bad_profile.yaml";
  std::ofstream(path) << "vehicles: [1, 99]\n";
  const Ran ran = run("run --worlds 1 --profile " + path);
  EXPECT_EQ(ran.code, 2);
  EXPECT_NE(ran.output.find(path + ":1:11: out of range"), std::string::npos) << ran.output;
}

TEST(CampaignProfile, ShippedProfilesLoad) {
  EXPECT_EQ(load_profile(shipped_profile_path("default")).name, "default");
  EXPECT_EQ(load_profile(shipped_profile_path("calm")).name, "calm");
  EXPECT_NE(load_profile(shipped_profile_path("default")).digest, load_profile(shipped_profile_path("calm")).digest);
}

}  // namespace
}  // namespace ocp::campaign
