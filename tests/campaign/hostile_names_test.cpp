// Injection through names (issue #36 item 2): a table of hostile names through every script
// and command line a campaign writes (the sbatch script, a failure's "Replay:" line). Each
// result is checked with `bash -n`, then run in a sandbox folder whose PATH leads to a stub that
// prints its arguments: no name may run a command, and each must reach the tool unchanged.
// A name with a control character is refused with exit 2.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "campaign/failure_files.hpp"
#include "campaign/profile.hpp"
#include "campaign/script_names.hpp"
#include "campaign/shell_words.hpp"
#include "campaign/slurm.hpp"
#include "child_process.hpp"

namespace ocp::campaign {
namespace {

namespace fs = std::filesystem;

// Each would run `touch PWNED` (or expand) if it reached a shell unquoted.
const std::vector<std::string> hostile_names = {
    "semi;touch PWNED",   "$(touch PWNED)",       "`touch PWNED`",  "it's \"x\" 'touch PWNED'", "100%a %j %%",
    "with space/and more", "back\\slash\\'",      "glob*?[a]",      "dash -x --y",               "&& touch PWNED ||",
    "héllo ✓ wörld",      "${HOME}$PATH",          "a|touch PWNED",  "!touch PWNED",              "~root"};
const std::vector<std::string> control_names = {"new\nline; touch PWNED", "carriage\rreturn", "tab\there", "bell\a",
                                                "del\x7f"};

struct ShellResult {
  int code = -1;
  std::string output;
};

ShellResult run_shell(const std::string& command) {
  const ocp::test::CommandRun ran = ocp::test::run_command(command);
  return ShellResult{ran.exit_code, ran.output};
}

void write_sandbox_file(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

std::string read_whole_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// A fresh sandbox with a stub tool that writes its arguments, one a line, to args.txt.
struct Sandbox {
  fs::path dir;
  explicit Sandbox(const std::string& name) : dir(fs::temp_directory_path() / ("ocp_hostile_names_" + name)) {
    fs::remove_all(dir);
    fs::create_directories(dir / "bin");
    const fs::path stub = dir / "bin" / "ocp_campaign";
    write_sandbox_file(stub, "#!/bin/sh\nfor a in \"$@\"; do printf '%s\\n' \"$a\"; done > \"$SANDBOX/args.txt\"\n");
    fs::permissions(stub, fs::perms::owner_all);
  }
  ~Sandbox() { fs::remove_all(dir); }
  fs::path stub() const { return dir / "bin" / "ocp_campaign"; }
  // Runs `script` (a file) under bash in the sandbox: `bash -n` first.
  ShellResult run(const fs::path& script, const std::string& env = "") const {
    const ShellResult syntax = run_shell("bash -n " + shell_quoted(script.string()));
    if (syntax.code != 0) return syntax;
    return run_shell("cd " + shell_quoted(dir.string()) + " && env " + env + " SANDBOX=" + shell_quoted(dir.string()) +
                     " PATH=" + shell_quoted((dir / "bin").string() + ":/usr/bin:/bin") + " bash " +
                     shell_quoted(script.string()));
  }
  bool pwned() const {
    for (const auto& entry : fs::recursive_directory_iterator(dir)) {
      if (entry.path().filename() == "PWNED") return true;
    }
    return false;
  }
  std::vector<std::string> args() const {
    std::vector<std::string> lines;
    std::istringstream in(read_whole_file(dir / "args.txt"));
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
  }
};

// The value after `option` in an argument list ("" when absent).
std::string value_after(const std::vector<std::string>& args, const std::string& option) {
  for (std::size_t i = 0; i + 1 < args.size(); ++i) {
    if (args[i] == option) return args[i + 1];
  }
  return "";
}

// sbatch's own reading of a directive's argument (src/sbatch/opt.c, _get_argument): quotes of
// either kind group, a backslash escapes the next character even inside quotes, an unquoted '#'
// ends the line.
std::string sbatch_argument(const std::string& text) {
  std::string out;
  char quote = 0;
  for (std::size_t at = 0; at < text.size(); ++at) {
    const char c = text[at];
    if (c == '\\' && at + 1 < text.size()) {
      out += text[++at];
    } else if (quote != 0) {
      if (c == quote) {
        quote = 0;
      } else {
        out += c;
      }
    } else if (c == '\'' || c == '"') {
      quote = c;
    } else if (c == ' ' || c == '#') {
      break;
    } else {
      out += c;
    }
  }
  return out;
}

// Slurm's filename pattern with %% as a literal % (the only escape the script uses).
std::string slurm_pattern_unescaped(const std::string& pattern) {
  std::string out;
  for (std::size_t at = 0; at < pattern.size(); ++at) {
    out += pattern[at];
    if (pattern[at] == '%' && at + 1 < pattern.size() && pattern[at + 1] == '%') ++at;
  }
  return out;
}

std::string directive(const std::string& script, const std::string& option) {
  std::istringstream in(script);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("#SBATCH " + option + "=", 0) == 0) return sbatch_argument(line.substr(8)).substr(option.size() + 1);
  }
  return "";
}

TEST(HostileNames, SbatchScriptQuotesEveryName) {
  for (const std::string& name : hostile_names) {
    SCOPED_TRACE(name);
    const Sandbox sandbox("sbatch");
    SlurmOptions options;
    options.out = (sandbox.dir / name).string();
    options.partition = name;
    options.profile = (sandbox.dir / ("p" + name + ".yaml")).string();
    const std::string script = sbatch_script(options, sandbox.stub().string());
    // Every line is the shebang, a directive, a comment or one of the two commands.
    std::istringstream lines(script);
    int commands = 0;
    for (std::string line; std::getline(lines, line);) {
      if (line.rfind("#", 0) != 0) ++commands;
    }
    EXPECT_EQ(commands, 2) << script;
    const fs::path out = fs::path(options.out).lexically_normal();
    EXPECT_EQ(slurm_pattern_unescaped(directive(script, "--output")), out.string() + "/shard-%a.log") << script;
    EXPECT_EQ(directive(script, "--partition"), name) << script;
    const fs::path file = sandbox.dir / "campaign.sbatch";
    write_sandbox_file(file, script);
    const ShellResult ran = sandbox.run(file, "SLURM_ARRAY_TASK_ID=3");
    EXPECT_EQ(ran.code, 0) << ran.output << script;
    EXPECT_FALSE(sandbox.pwned()) << script;
    const auto args = sandbox.args();
    EXPECT_EQ(value_after(args, "--profile"), fs::path(options.profile).lexically_normal().string()) << script;
    EXPECT_EQ(value_after(args, "--out"), out.string() + "/shard-3") << script;
  }
}

TEST(HostileNames, SbatchScriptRefusesControlCharacters) {
  for (const std::string& name : control_names) {
    SlurmOptions options;
    options.out = "results/" + name;
    EXPECT_THROW(sbatch_script(options, "/bin/true"), std::invalid_argument);
    options.out = "results";
    options.partition = name;
    EXPECT_THROW(sbatch_script(options, "/bin/true"), std::invalid_argument);
  }
}

TEST(HostileNames, CommandLineRefusesControlCharactersWithExitTwo) {
  const std::string tool = OCP_CAMPAIGN_PATH;
  const std::vector<std::string> options = {"slurm --print-only --out", "slurm --print-only --partition",
                                            "slurm --print-only --profile", "run --worlds 1 --out", "run --worlds 1 --profile"};
  for (const std::string& option : options) {
    for (const std::string& name : control_names) {
      SCOPED_TRACE(option + " " + name);
      const ShellResult ran = run_shell(shell_quoted(tool) + " " + option + " " + shell_quoted(name));
      EXPECT_EQ(ran.code, 2) << ran.output;
      EXPECT_NE(ran.output.find("control character"), std::string::npos) << ran.output;
      EXPECT_EQ(ran.output.find("PWNED\n"), std::string::npos) << ran.output;
    }
  }
}

// The "Replay:" line of a failure's world.yaml, pasted into a shell in the sandbox.
TEST(HostileNames, ReplayLineQuotesTheProfile) {
  const Profile profile = load_profile(shipped_profile_path("calm"));
  for (const std::string& name : hostile_names) {
    SCOPED_TRACE(name);
    const Sandbox sandbox("replay");
    FailureFilesOptions options;
    options.out_dir = (sandbox.dir / "results").string();
    options.campaign_seed = 3;
    options.worlds = 5;
    options.profile_argument = name + ".yaml";
    options.shrink = false;
    write_failure_files(profile, 2, options);
    // The file's header comment, as a person reads it and pastes it.
    const std::string yaml = read_whole_file(sandbox.dir / "results/failures/world-2/world.yaml");
    const auto at = yaml.find("Replay: ");
    ASSERT_NE(at, std::string::npos) << yaml;
    const std::string line = yaml.substr(at + 8, yaml.find('\n', at) - at - 8);
    const fs::path file = sandbox.dir / "replay.sh";
    write_sandbox_file(file, line + "\n");
    const ShellResult ran = sandbox.run(file);
    EXPECT_EQ(ran.code, 0) << ran.output << line;
    EXPECT_FALSE(sandbox.pwned()) << line;
    const auto args = sandbox.args();
    EXPECT_EQ(value_after(args, "--profile"), name + ".yaml") << line;
    EXPECT_EQ(value_after(args, "--world"), "2") << line;
  }
}

}  // namespace
}  // namespace ocp::campaign
