#pragma once
// Reading checked values out of yaml-cpp nodes; every failure throws ScenarioError with the
// node's position. Internal to the parser.
#include <yaml-cpp/yaml.h>

#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include "scenario/model.hpp"
#include "scenario/parse.hpp"

namespace ocp::scenario {

class YamlReader {
 public:
  explicit YamlReader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const YAML::Node& node, const std::string& reason) const;
  Mark mark(const YAML::Node& node) const;

  // The node must be a map whose keys are all in `allowed`.
  void check_keys(const YAML::Node& node, std::string_view what,
                  std::initializer_list<std::string_view> allowed) const;
  // "unknown <what> '<word>': did you mean …?" (did_you_mean.hpp), at the node.
  [[noreturn]] void fail_unknown(const YAML::Node& node, std::string_view what, const std::string& word,
                                 const std::vector<std::string>& known) const;
  // A required key of a map.
  YAML::Node require(const YAML::Node& map, const char* key, std::string_view what) const;

  std::string text(const YAML::Node& node) const;
  bool boolean(const YAML::Node& node) const;
  double number(const YAML::Node& node, double min, double max) const;
  std::uint64_t integer(const YAML::Node& node) const;
  Micros duration(const YAML::Node& node) const;   // "350ms", "12.5s"; 0 alone is allowed
  // Any YAML value as one JSON value (user data): scalars that read as numbers, booleans or
  // null become those; everything else a string.
  std::string json(const YAML::Node& node) const;

  const std::string& file() const { return file_; }

 private:
  std::string file_;
};

}  // namespace ocp::scenario
