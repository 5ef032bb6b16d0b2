// Scenario file → Scenario (the format: docs/scenarios.md, scenario/scenario.schema.json).
// One pass over the YAML tree; every check fails with the offending node's line and column.
// The sections are read in parse_world.cpp, parse_timeline.cpp and parse_expect.cpp.
#include "scenario/parse.hpp"

#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "parser.hpp"
#include "ocp/bounded_file.hpp"
#include "yaml_syntax.hpp"

namespace ocp::scenario {

std::string format_time(Micros time) {
  const auto us = time.count();
  if (us % 1'000'000 == 0) return std::to_string(us / 1'000'000) + "s";
  if (us % 1000 == 0) return std::to_string(us / 1000) + "ms";
  return std::to_string(us) + "us";
}

Scenario Parser::parse(const std::string& text) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::DeepRecursion& error) {
    throw ScenarioError(read_.file(), error.mark.line + 1, error.mark.column + 1,
                        "nested deeper than " + std::to_string(error.depth() - 1) +
                            " levels of lists or mappings (YAML refuses more)");
  } catch (const YAML::ParserException& error) {
    throw ScenarioError(read_.file(), error.mark.line + 1, error.mark.column + 1,
                        explain_yaml_syntax_error(error.msg, text, error.mark.line + 1));
  }
  if (!root || root.IsNull()) throw ScenarioError(read_.file(), 1, 1, "empty scenario file");
  read_.check_keys(root, "scenario", {"description", "seed", "duration", "world", "timeline", "expect"});
  scenario_.name = std::filesystem::path(scenario_.path).stem().string();
  if (root["description"]) scenario_.description = read_.text(root["description"]);
  if (root["seed"]) scenario_.seed = read_.integer(root["seed"]);
  scenario_.duration = read_.duration(read_.require(root, "duration", "scenario"));
  if (scenario_.duration <= Micros{0}) read_.fail(root["duration"], "duration must be > 0");
  if (scenario_.duration > parse_limits().max_run_duration) {
    read_.fail(root["duration"], "duration " + format_time(scenario_.duration) + " is over the ceiling of one run, " +
                                     format_time(parse_limits().max_run_duration) + " simulated (raise it with --max-simulated-h)");
  }
  if (const YAML::Node expect = root["expect"]; expect && expect.IsMap()) expects_refusal_ = static_cast<bool>(expect["refuses_to_start"]);
  world(read_.require(root, "world", "scenario"));
  if (root["timeline"]) timeline(root["timeline"]);
  expectations(read_.require(root, "expect", "scenario"));
  return std::move(scenario_);
}


Scenario parse_scenario(const std::string& text, const std::string& path) {
  try {
    return Parser(path).parse(text);
  } catch (const YAML::Exception& error) {
    // yaml-cpp's own conversions (a non-scalar key, …) carry a position too.
    throw ScenarioError(path, error.mark.line + 1, error.mark.column + 1, error.msg);
  }
}

Scenario load_scenario(const std::string& path) {
  // The system's reason (no such file, permission denied), or why the file is refused (not a
  // regular file, over the cap): ocp/bounded_file.hpp.
  auto text = read_bounded_file(path, file_kinds::scenario);
  if (!text) throw ScenarioError(path, text.error().detail);
  return parse_scenario(*text, path);
}

}  // namespace ocp::scenario
