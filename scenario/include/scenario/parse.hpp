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

// "12.5s", "350ms", "250us", "2min" → µs. Throws std::invalid_argument with the reason, also
// for a duration beyond max_duration_us (the sums of times would overflow beyond it).
Micros parse_duration_text(const std::string& text);
inline constexpr std::int64_t max_duration_us = std::int64_t{1} << 62;

// The ceilings of one run (docs/usage.md, "Input files"): a longer `duration`, a faster
// `client_data every`, or a YAML value (user data, expected user data) that expands to more
// nodes is refused with exit 2. The tools' --max-simulated-h raises the first. A virtual-time
// run that runs more than max_events_per_s executor events in one simulated second (a
// `control_period: 1us`, a thousand cameras) stops there with a HarnessError (exit 2);
// --max-events-per-s raises it.
struct ParseLimits {
  Micros max_run_duration{24LL * 3600 * 1'000'000};   // simulated time per run
  Micros min_every{1'000};                             // at most 1 000 client_data events a second
  std::uint64_t max_events_per_s = 1'000'000;          // about 1 000 vehicles at the product's rates
  std::size_t max_value_nodes = 100'000;               // nodes of one user-data value, aliases expanded
};
const ParseLimits& parse_limits();
void set_parse_limits(const ParseLimits& limits);

}  // namespace ocp::scenario
