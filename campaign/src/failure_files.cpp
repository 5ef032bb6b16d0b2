// A failing world's folder (failure_files.hpp).
#include "campaign/failure_files.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "campaign/client_world.hpp"
#include "campaign/generator.hpp"
#include "campaign/shell_words.hpp"
#include "campaign/shrink.hpp"
#include "campaign/world_check.hpp"
#include "scenario/reports.hpp"
#include "scenario/verdicts.hpp"
#include "scenario/write.hpp"

namespace ocp::campaign {

namespace {

void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

// A generated world has no expectations; a scenario file must have one.
scenario::Scenario with_placeholder_expectation(scenario::Scenario world) {
  if (world.expectations.empty()) {
    world.expectations.push_back(
        {"", {}, scenario::InvariantExpectation{scenario::Invariant::default_controller_during_control_fault}});
  }
  return world;
}

std::string replay_command(std::uint64_t index, const FailureFilesOptions& options) {
  std::string command = "ocp_campaign run --seed " + std::to_string(options.campaign_seed) + " --worlds " +
                        std::to_string(options.worlds) + " --profile " + shell_quoted(options.profile_argument) + " --world " +
                        std::to_string(index);
  if (options.client) {
    command += " --client " + shell_quoted(options.client->command);
    if (options.client->max_world_seconds) {
      command += " --max-world-seconds " + fmt::format("{:g}", *options.client->max_world_seconds);
    }
    command += options.client->run ? " --time virtual" : " --time real";
  }
  return command;
}

}  // namespace

FailureFiles write_failure_files(const Profile& profile, std::uint64_t index, const FailureFilesOptions& options) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(options.out_dir) / ("failures/world-" + std::to_string(index));
  fs::create_directories(dir);
  scenario::Scenario world = generate_world(profile, options.campaign_seed, index);
  if (options.client) world = for_external_client(std::move(world), index, options.client->max_world);
  FailureFiles made;
  made.replay = replay_command(index, options);
  write_text(dir / "world.yaml",
             scenario::write_scenario_yaml(with_placeholder_expectation(world), "World " + std::to_string(index) +
                                                                                    " as generated.\nReplay: " + made.replay));
  made.files.push_back("world.yaml");
  if (options.client) {
    if (!options.client->run || !options.shrink) return made;
    // Virtual time: every try is a fast, exact run of the client itself.
    const ClientRun& run = *options.client->run;
    const WorldChecker with_client = [&](const scenario::Scenario& candidate) {
      return check_world_with_client(candidate, index, run, {});
    };
    const WorldOutcome outcome = with_client(world);
    if (outcome.violations.empty()) return made;
    const ShrinkResult shrunk = shrink(world, ShrinkTarget::of(outcome.violations.front()),
                                       std::min(options.shrink_runs, client_shrink_runs), with_client);
    write_text(dir / "shrunk.yaml", regression_yaml(shrunk, made.replay));
    made.files.push_back("shrunk.yaml");
    made.shrunk_events = static_cast<int>(shrunk.scenario.timeline.size());
    return made;
  }
  const WorldOutcome outcome = check_world(world, {true});
  if (outcome.violations.empty() || !options.shrink) return made;
  const ShrinkResult shrunk = shrink(world, ShrinkTarget::of(outcome.violations.front()), options.shrink_runs);
  const std::string check_command = "ocp_campaign check " + shell_quoted((dir / "shrunk.yaml").string());
  write_text(dir / "shrunk.yaml", regression_yaml(shrunk, check_command));
  made.files.push_back("shrunk.yaml");
  // The scenario runner's own report of the shrunk world, as for any scenario.
  scenario::Scenario report_world = with_placeholder_expectation(shrunk.scenario);
  const scenario::RunResult run = run_for_report(report_world);
  scenario::RunReport report{&report_world, &run, scenario::evaluate(report_world, run), check_command};
  write_text(dir / "report.html", scenario::report_html(report, scenario::summary_json(report)));
  made.files.push_back("report.html");
  made.shrunk_events = static_cast<int>(shrunk.scenario.timeline.size());
  return made;
}

}  // namespace ocp::campaign
