#pragma once
// Scenario files (docs/scenarios.md): YAML → a validated Scenario. Every mistake — unknown key,
// bad value, event out of order, an expectation that names nothing — is a ScenarioError that
// says file:line:column and why. The CLI turns it into exit code 2.
#include <stdexcept>
#include <string>

#include "scenario/model.hpp"

namespace ocp::scenario {

class ScenarioError : public std::runtime_error {
 public:
  ScenarioError(std::string file, int line, int column, std::string reason);
  // About the file as a whole (it cannot be opened): what() is `message` alone, line 0.
  ScenarioError(std::string file, std::string message);
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  int column() const { return column_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string file_;
  int line_, column_;
  std::string reason_;
};

// `path` names the file in errors and gives the scenario its name (the stem).
Scenario parse_scenario(const std::string& text, const std::string& path);
Scenario load_scenario(const std::string& path);   // reads the file, then parse_scenario

// "12.5s", "350ms", "250us", "2min" → µs. Throws std::invalid_argument with the reason.
Micros parse_duration_text(const std::string& text);

}  // namespace ocp::scenario
